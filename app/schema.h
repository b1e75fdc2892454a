// The script API's parameters: one table gives names, types, defaults, ranges, units and docs.
#pragma once

#include <cstdlib>
#include <string>
#include <vector>

namespace cellform::app {

/// What kind of value a parameter takes.
enum class Kind {
  number,
  integer,
  boolean,
  vec3,
  text,
  choice,
  function,
  choice_or_function,
  number_or_function,
  table,
  table_or_function
};

/// One parameter of one script function (a "section" such as cells{} or division{}).
struct Field {
  std::string section;  ///< the script function it belongs to, e.g. "cells"
  std::string name;     ///< e.g. "rest_length"
  Kind kind = Kind::number;
  std::string default_text;    ///< default as the docs show it ("" = required or none)
  double min = -1e300;         ///< smallest allowed value (numbers, integers, each vector component)
  double max = 1e300;          ///< largest allowed value
  bool min_exclusive = false;  ///< true: value must be strictly greater than min
  std::string choices;         ///< allowed names for choice kinds, separated by '|'
  std::string unit;            ///< unit or role, e.g. "model units"
  std::string doc;             ///< one line
  double nonzero_min = 0;      ///< > 0: besides 0 (an automatic value), nothing below this is allowed (checked
                               ///< with the range, script and --set alike)
  /// A function or table: leaving it out is no error, whatever default_text says.
  bool structured() const { return kind == Kind::function || kind == Kind::table || kind == Kind::table_or_function; }
};

/// Every parameter of every script function, in documentation order.
const std::vector<Field>& schema();

/// Model units: no script position or direction may lie farther out (their squares would overflow, and no
/// form is that big).
inline constexpr double kFarthest = 1e9;

/// The fields of one section.
std::vector<const Field*> section_fields(const std::string& section);

/// The field, or nullptr.
const Field* find_field(const std::string& section, const std::string& name);

/// Markdown tables documenting every section (docs/scripting.md quotes this; `cellform params` prints it).
std::string schema_markdown();

/// "0 <= x <= 1"-style description of a field's allowed values.
std::string allowed_text(const Field& f);

/// `s` without leading and trailing spaces and tabs.
inline std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  const auto b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

/// A --set value read as a number, as every --set of a number is (spaces around it allowed, strtod's forms).
inline bool parse_double(const std::string& text, double& out) {
  const std::string t = trim(text);
  if (t.empty()) return false;
  char* end = nullptr;
  out = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size();
}

}  // namespace cellform::app
