#include "framework/text.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>

namespace rome {

// Length of the valid UTF-8 sequence starting at s[i], or 0 if it is not valid UTF-8.
size_t Utf8SequenceLength(const std::string& s, size_t i) {
  const auto b = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;
  if (c >= 0xC2 && c <= 0xDF)
    n = 2;
  else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  } else
    return 0;
  if (i + n > s.size()) return 0;
  if (b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (size_t k = 2; k < n; ++k)
    if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
  return n;
}

bool IsValidUtf8(const std::string& s) {
  for (size_t i = 0; i < s.size();) {
    const size_t n = Utf8SequenceLength(s, i);
    if (n == 0) return false;
    i += n;
  }
  return true;
}

std::string Excerpt(const std::string& s, size_t max_chars) {
  std::string out;
  size_t i = 0, shown = 0;
  char buf[8];
  for (; i < s.size() && shown < max_chars; ++shown) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const size_t n = Utf8SequenceLength(s, i);
    if (n == 1 && c >= 0x20 && c != 0x7F) {
      out += static_cast<char>(c);
    } else if (n > 1) {
      out.append(s, i, n);
    } else {
      std::snprintf(buf, sizeof(buf), "\\x%02X", c);
      out += buf;
      i += 1;
      continue;
    }
    i += n;
  }
  if (i < s.size()) out += "... (" + std::to_string(s.size()) + " bytes)";
  return out;
}

namespace {

// Calls emit(code_point, bytes) for each UTF-8 sequence of s; an invalid byte is U+FFFD.
template <typename Emit>
void ForEachCodePoint(const std::string& s, Emit emit) {
  for (size_t i = 0; i < s.size();) {
    const size_t n = Utf8SequenceLength(s, i);
    if (n == 0) {
      emit(0xFFFDu, std::string_view("\xEF\xBF\xBD"));
      ++i;
      continue;
    }
    const auto b = [&](size_t k) { return static_cast<unsigned char>(s[i + k]) & 0x3Fu; };
    const unsigned c0 = static_cast<unsigned char>(s[i]);
    const unsigned cp = n == 1   ? c0
                        : n == 2 ? ((c0 & 0x1Fu) << 6) | b(1)
                        : n == 3 ? ((c0 & 0x0Fu) << 12) | (b(1) << 6) | b(2)
                                 : ((c0 & 0x07u) << 18) | (b(1) << 12) | (b(2) << 6) | b(3);
    emit(cp, std::string_view(s.data() + i, n));
    i += n;
  }
}

}  // namespace

std::string JsonStringForScript(const std::string& s) {
  std::string out = "\"";
  char buf[16];
  ForEachCodePoint(s, [&](unsigned cp, std::string_view bytes) {
    if (cp == '"')
      out += "\\\"";
    else if (cp == '\\')
      out += "\\\\";
    else if (cp < 0x20 || cp == '<' || cp == '>' || cp == '&' || cp == 0x7F || cp == 0x2028 || cp == 0x2029) {
      std::snprintf(buf, sizeof(buf), "\\u%04X", cp);
      out += buf;
    } else {
      out += bytes;
    }
  });
  return out + "\"";
}

std::string HtmlText(const std::string& s) {
  std::string out;
  ForEachCodePoint(s, [&](unsigned cp, std::string_view bytes) {
    switch (cp) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default:
        if ((cp < 0x20 && cp != '\t' && cp != '\n') || (cp >= 0x7F && cp < 0xA0))
          out += "\xEF\xBF\xBD";
        else
          out += bytes;
    }
  });
  return out;
}

std::string GnuplotString(const std::string& s) {
  // Gnuplot's tokenizer reads a leading or trailing '' as an empty string, so a quote cannot be doubled; it is joined
  // in as sprintf('%c',39) instead.
  std::string out = "'";
  ForEachCodePoint(s, [&](unsigned cp, std::string_view bytes) {
    if (cp == '\'')
      out += "'.sprintf('%c',39).'";
    else if (cp < 0x20 || cp == 0x7F)
      out += ' ';
    else
      out += bytes;
  });
  return out + "'";
}

std::string CsvCell(const std::string& s) {
  std::string cell = s;
  double number = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), number);
  const bool is_number = !s.empty() && ec == std::errc() && end == s.data() + s.size() && std::isfinite(number);
  if (!cell.empty() && !is_number && std::string_view("=+-@\t\r").find(cell.front()) != std::string_view::npos)
    cell.insert(0, 1, '\'');
  if (cell.find_first_of(",\"\r\n") == std::string::npos) return cell;
  std::string out = "\"";
  for (char c : cell) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace rome
