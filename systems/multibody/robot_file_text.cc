#include "systems/multibody/robot_file_text.h"

#include <cctype>
#include <cstdio>
#include <cstring>
#include <set>
#include <stdexcept>
#include <vector>

#include "framework/text.h"
#include "systems/multibody/multibody_model.h"

namespace rome {

namespace {

using json = nlohmann::json;

[[noreturn]] void FailUrdf(const std::string& path, size_t line, const std::string& problem) {
  throw std::runtime_error("URDF " + Excerpt(path, 200) + ": line " + std::to_string(line) + ": " + problem);
}

// TinyXML 2.6.2 (under urdfdom) steps over a NUL that ends a truncated multi-byte sequence and reads past the buffer
// (a heap overflow found by tests/fuzz/urdf_sidecar_fuzzer): the text must be UTF-8 without NUL bytes.
void CheckXmlEncoding(const std::string& xml, const std::string& path) {
  size_t line = 1;
  for (size_t i = 0; i < xml.size();) {
    const size_t n = xml[i] == '\0' ? 0 : Utf8SequenceLength(xml, i);
    if (n == 0) {
      char byte[8];
      std::snprintf(byte, sizeof(byte), "0x%02X", static_cast<unsigned>(static_cast<unsigned char>(xml[i])));
      FailUrdf(path, line,
               std::string("byte ") + byte + " at offset " + std::to_string(i) +
                   (xml[i] == '\0' ? " is a NUL byte" : " is not valid UTF-8") + "; a URDF must be UTF-8 text");
    }
    line += xml[i] == '\n';
    i += n;
  }
}

// The element name at the start of a tag's text ("<name attr=...>").
std::string ElementName(const std::string& xml, size_t open, size_t end) {
  size_t k = open + 1;
  while (k < end && !std::isspace(static_cast<unsigned char>(xml[k])) && xml[k] != '/' && xml[k] != '>') ++k;
  return xml.substr(open + 1, k - open - 1);
}

// One opening tag: the xacro and <robot> rules (depth = the tag's depth, 0 at the top).
void CheckElement(const std::string& xml, const std::string& path, size_t open, size_t end, int depth, size_t line,
                  int* robots) {
  const std::string name = ElementName(xml, open, end);
  const std::string tag = xml.substr(open, end - open + 1);
  if (name.rfind("xacro:", 0) == 0 || tag.find("xmlns:xacro") != std::string::npos ||
      tag.find("${") != std::string::npos || tag.find("$(") != std::string::npos)
    FailUrdf(path, line,
             "xacro in " + Excerpt(tag, 80) +
                 ": this is a xacro file, not a URDF; expand it with xacro first "
                 "(xacro ROBOT.urdf.xacro > ROBOT.urdf)");
  if (depth == 0 && name == "robot" && ++*robots > 1)
    FailUrdf(path, line,
             "a second <robot> element; a URDF describes one robot (urdfdom would read the first and drop the rest)");
}

}  // namespace

// Scanned without building a tree, so that a pathological file is refused before the (recursive) XML parser sees it.
// Handles comments, CDATA, processing instructions, declarations and quoted attribute values.
void CheckXmlText(const std::string& xml, const std::string& path) {
  CheckXmlEncoding(xml, path);
  int depth = 0, robots = 0;
  size_t line = 1;
  const size_t n = xml.size();
  auto skip_to = [&](size_t& i, const char* end) {
    const size_t k = xml.find(end, i);
    for (size_t j = i; j < (k == std::string::npos ? n : k); ++j) line += xml[j] == '\n';
    i = k == std::string::npos ? n : k + std::strlen(end);
  };
  for (size_t i = 0; i < n;) {
    const char c = xml[i];
    if (c == '\n') ++line;
    if (c != '<') {
      ++i;
      continue;
    }
    if (xml.compare(i, 4, "<!--") == 0) {
      i += 4;
      skip_to(i, "-->");
      continue;
    }
    if (xml.compare(i, 9, "<![CDATA[") == 0) {
      i += 9;
      skip_to(i, "]]>");
      continue;
    }
    if (xml.compare(i, 2, "<?") == 0) {
      i += 2;
      skip_to(i, "?>");
      continue;
    }
    if (xml.compare(i, 2, "<!") == 0) {
      i += 2;
      skip_to(i, ">");
      continue;
    }
    const bool closing = i + 1 < n && xml[i + 1] == '/';
    const size_t tag_line = line;
    size_t j = i + 1;  // scan to the end of the tag, skipping quoted attribute values
    char quote = 0;
    for (; j < n; ++j) {
      if (xml[j] == '\n') ++line;
      if (quote) {
        if (xml[j] == quote) quote = 0;
      } else if (xml[j] == '"' || xml[j] == '\'')
        quote = xml[j];
      else if (xml[j] == '>')
        break;
    }
    const bool self_closing = j < n && j > i + 1 && xml[j - 1] == '/';
    if (closing) {
      // A closing tag with no element open: the parser would skip it, and the depth and <robot> counts would drift.
      if (depth == 0)
        FailUrdf(path, tag_line, Excerpt(xml.substr(i, std::min(j, n - 1) - i + 1), 80) + " closes no element");
      --depth;
    } else {
      CheckElement(xml, path, i, std::min(j, n - 1), depth, tag_line, &robots);
      if (!self_closing && ++depth > kMaxXmlDepth)
        FailUrdf(path, line,
                 "XML elements nested more than " + std::to_string(kMaxXmlDepth) +
                     " deep (a URDF needs fewer than 10 levels)");
    }
    i = j + 1;
  }
}

json ParseSidecarJson(const std::string& text, const std::string& file_path) {
  return ParseJsonStrict(text, "sidecar " + Excerpt(file_path, 200));
}

namespace {

// The strict checks as a SAX pass (linear in the text): nesting depth and duplicate keys, in the order they occur. The
// DOM parser's callback form is not used for this: it rescans an array's elements after each object that ends inside
// it (quadratic: 200,000 contacts took 158 s).
class StrictJsonChecker final : public json::json_sax_t {
 public:
  explicit StrictJsonChecker(const std::string& file) : file_(file) {}
  bool null() override { return Value(); }
  bool boolean(bool) override { return Value(); }
  bool number_integer(number_integer_t) override { return Value(); }
  bool number_unsigned(number_unsigned_t) override { return Value(); }
  bool number_float(number_float_t, const string_t&) override { return Value(); }
  bool string(string_t&) override { return Value(); }
  bool binary(binary_t&) override { return Value(); }
  bool start_object(std::size_t) override { return Open(true); }
  bool start_array(std::size_t) override { return Open(false); }
  bool end_object() override { return Close(); }
  bool end_array() override { return Close(); }
  bool key(string_t& k) override {
    last_key_ = k;
    if (!keys_.back().insert(k).second)
      throw std::runtime_error(
          file_ + ": " + (path_.back().empty() ? std::string("top level") : Excerpt(path_.back(), 80)) + ": key '" +
          Excerpt(k, 60) + "' appears twice (JSON would keep only the last); write it once");
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    throw std::runtime_error(file_ + ": malformed JSON: " + Excerpt(e.what(), 200));
  }

 private:
  bool Value() { return true; }
  bool Open(bool object) {
    if (static_cast<int>(path_.size()) >= kMaxJsonDepth)
      throw std::runtime_error(file_ + ": objects and arrays nested more than " + std::to_string(kMaxJsonDepth) +
                               " deep");
    // Its key path ("" at the top; "a.b", "a[]"), for the messages.
    const std::string parent = path_.empty() ? "" : path_.back();
    const bool in_array = !is_object_.empty() && !is_object_.back();
    path_.push_back(path_.empty()    ? ""
                    : in_array       ? parent + "[]"
                    : parent.empty() ? last_key_
                                     : parent + "." + last_key_);
    keys_.emplace_back();
    is_object_.push_back(object);
    return true;
  }
  bool Close() {
    keys_.pop_back();
    path_.pop_back();
    is_object_.pop_back();
    return true;
  }
  const std::string& file_;
  std::vector<std::set<std::string>> keys_;  // per open object or array: its keys so far
  std::vector<std::string> path_;
  std::vector<bool> is_object_;
  std::string last_key_;
};

}  // namespace

json ParseJsonStrict(const std::string& text, const std::string& file) {
  StrictJsonChecker checker(file);
  json::sax_parse(text, &checker, json::input_format_t::json, /*strict=*/true, /*ignore_comments=*/true);
  try {
    return json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const json::exception& e) { throw std::runtime_error(file + ": malformed JSON: " + Excerpt(e.what(), 200)); }
}

// " (line N: NaN in name="...")" for the first attribute value holding a NaN or an infinity (urdfdom only says
// "not a valid double"), else "".
std::string NonFiniteNumberHint(const std::string& xml) {
  size_t line = 1;
  for (size_t i = 0; i < xml.size(); ++i) {
    if (xml[i] == '\n') {
      ++line;
      continue;
    }
    if (xml[i] != '"' && xml[i] != '\'' && xml[i] != ' ') continue;
    size_t j = i + 1;
    if (j < xml.size() && (xml[j] == '-' || xml[j] == '+')) ++j;
    std::string word;
    while (j < xml.size() && word.size() < 8 && std::isalpha(static_cast<unsigned char>(xml[j])))
      word += static_cast<char>(std::tolower(static_cast<unsigned char>(xml[j++])));
    if (j >= xml.size() || (xml[j] != '"' && xml[j] != '\'' && xml[j] != ' ')) continue;
    if (word == "nan" || word == "inf" || word == "infinity") {
      const size_t tag = xml.rfind('<', i);
      const size_t end = tag == std::string::npos ? std::string::npos : xml.find('>', tag);
      const std::string element =
          tag == std::string::npos ? "" : xml.substr(tag, end == std::string::npos ? 120 : end - tag + 1);
      return " (line " + std::to_string(line) + ": " + (word == "nan" ? "NaN" : "infinity") + " in " +
             Excerpt(element, 120) + ")";
    }
  }
  return "";
}

}  // namespace rome
