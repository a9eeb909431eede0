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

/// Escaping for one output language each; every string that comes from an input (a robot's names, a path, a label)
/// goes through the function of the language it is written into. Invalid UTF-8 bytes become U+FFFD in all four.

/// A JSON string literal, quotes included, that is also safe inside an HTML <script> element: besides `"`, `\` and
/// control characters, `<`, `>`, `&`, U+2028 and U+2029 are written as \uXXXX, so the text can neither end the
/// script element nor a JavaScript string. JSON.parse of the result gives s back (for valid UTF-8 s).
std::string JsonStringForScript(const std::string& s);

/// HTML text and attribute values: `&`, `<`, `>`, `"` and `'` as entities; control characters but tab and newline
/// as U+FFFD (HTML forbids them).
std::string HtmlText(const std::string& s);

/// A gnuplot string expression: single-quoted pieces, each `'` joined in as sprintf('%c',39), and control characters
/// (a newline would end the command) as spaces. Gnuplot expands neither backquotes nor `@` macros nor backslash
/// escapes in single quotes, so no text can run a command.
std::string GnuplotString(const std::string& s);

/// One CSV cell (RFC 4180): quoted when it has `,`, `"`, CR or LF (with `"` doubled), and, unless it is a finite
/// number ("-0.5" stays a number), prefixed with `'` when it starts with `=`, `+`, `-`, `@`, tab or CR, so a
/// spreadsheet never reads it as a formula.
std::string CsvCell(const std::string& s);

/// A short, printable, one-line excerpt of s: control bytes and invalid UTF-8 are escaped as \xNN, valid UTF-8 is
/// kept, and text beyond max_chars characters is cut with "... (N bytes)".
std::string Excerpt(const std::string& s, size_t max_chars = 80);

}  // namespace rome
