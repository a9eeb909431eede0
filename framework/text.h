#pragma once
// Text helpers for error messages built from untrusted input (file paths, names, lines of a file): every message
// ROME prints stays one short, printable line, whatever bytes the input held.

#include <cstddef>
#include <string>

namespace rome {

/// Length of the valid UTF-8 sequence starting at s[i] (1-4), or 0 if none starts there.
size_t Utf8SequenceLength(const std::string& s, size_t i);

/// Whether all of s is valid UTF-8.
bool IsValidUtf8(const std::string& s);

/// A short, printable, one-line excerpt of s: control bytes and invalid UTF-8 are escaped as \xNN, valid UTF-8 is
/// kept, and text beyond max_chars characters is cut with "... (N bytes)".
std::string Excerpt(const std::string& s, size_t max_chars = 80);

}  // namespace rome
