#pragma once
// Checks of a robot description's raw text, before a parser builds anything from it (MultibodyModel's loader uses them;
// each throws std::runtime_error with one line naming the file, the line or key, and what is expected):
//   CheckXmlText      UTF-8 without NUL bytes; elements nested at most kMaxXmlDepth deep; exactly one <robot> element
//                     at the top; no xacro left in the file (<xacro:...> elements, xmlns:xacro, ${...} or $(...)):
//                     "expand it with xacro first".
//   ParseSidecarJson  JSON with comments, nested at most kMaxJsonDepth deep (checked while parsing, before any value
//                     is printed), and no key twice in one object (the last one would silently win); ParseJsonStrict
//                     does the same for any JSON file a user writes.
//   NonFiniteNumberHint  " (line N: NaN in <element>)" for the first NaN or infinity among the XML's attribute values.

#include <string>

#include <nlohmann/json.hpp>

namespace rome {

/// Deepest nesting of objects and arrays a sidecar may have (ours: a sidecar needs 4 levels).
inline constexpr int kMaxJsonDepth = 64;

void CheckXmlText(const std::string& xml, const std::string& path);
nlohmann::json ParseSidecarJson(const std::string& text, const std::string& path);
/// The same checks for any JSON file a user writes (a scenario file, ...); `file` names it in the messages
/// ("<file>: top level: key 'x' appears twice ...").
nlohmann::json ParseJsonStrict(const std::string& text, const std::string& file);
std::string NonFiniteNumberHint(const std::string& xml);

}  // namespace rome
