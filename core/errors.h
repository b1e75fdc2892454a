// The small exception hierarchy every module throws for problems a user can act on.
#pragma once

#include <algorithm>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cellform::core {

/// Bad input from a user: a parameter, a script, a file. The message says what, where and what is allowed.
class InvalidInput : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A simulation left the range where its numbers mean anything (NaN, infinite or exploding values).
class SimulationDiverged : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file could not be read or written (missing, unwritable, full disk, corrupt, foreign format).
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A long operation was asked to stop by its progress callback (Ctrl-C on the command line).
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

/// A number for a message: up to 6 significant digits, 1e+300 and 1e-300 as such (std::to_string would
/// print 300 digits, or 0.000000); negative zero as 0.
std::string number_text(double x);

/// A point for a message, as a script writes it: "{x, y, z}" with number_text's numbers.
std::string point_text(double x, double y, double z);

/// What went wrong, for a message: e.what(), but an allocation that failed (std::bad_alloc, whose what()
/// says only "std::bad_alloc") is said in words.
std::string error_text(const std::exception& e);

/// `text` (a name or word read from a file) safe to show in a one-line message: control bytes, NUL and
/// DEL become \xNN, so that a damaged file cannot clear a terminal, move its cursor or cut the message;
/// so do bytes that are not part of well-formed UTF-8 (a binary file's header) and the C1 controls
/// U+0080 to U+009F; other UTF-8 text stays.
std::string printable(std::string_view text);

/// Whether `text` is well-formed UTF-8 (what JSON, and so run.json and a checkpoint, can hold).
bool is_utf8(std::string_view text);

/// Edit distance counting insertions, deletions, substitutions and swaps of neighbouring letters (optimal
/// string alignment); used to suggest the closest valid name for a misspelt one.
std::size_t edit_distance(const std::string& a, const std::string& b);

/// `text` in lower case (ASCII letters).
std::string lower_case(std::string text);

/// The candidate closest to `name`, or "" if none is reasonably close: letter case aside, at most a third of
/// `name`'s letters changed, and one at least ("nope" is not a misspelt "type"); else the one candidate that
/// begins `name` or that `name` begins, of 4 letters or more and at least 0.6 of the longer ("printing" for
/// "print", not "checkpoint" for "check"; none when several do: "--lua" begins three options).
template <class Range>
std::string closest_name(const std::string& name, const Range& candidates) {
  const std::string key = lower_case(name);
  std::string best;
  std::size_t best_d = std::max<std::size_t>(name.size() / 3, 1) + 1, best_prefix = 0;
  for (const auto& c : candidates) {
    std::string s(c);
    const std::string l = lower_case(s);
    const std::size_t d = edit_distance(key, l);
    std::size_t prefix = 0;  // letters it shares with `name` from the start: "--steep" is "--steps", not "--seed"
    while (prefix < l.size() && prefix < key.size() && l[prefix] == key[prefix]) ++prefix;
    if (d < best_d || (d == best_d && d == 0 && s == name) ||  // the very name before one in other letters
        (d == best_d && d > 0 && !best.empty() && prefix > best_prefix)) {
      best_d = d;
      best = s;
      best_prefix = prefix;
    }
  }
  if (!best.empty()) return best;
  std::size_t found = 0;
  for (const auto& c : candidates) {
    const std::string s(c), l = lower_case(s);
    const std::size_t common = std::min(l.size(), key.size());
    if (common >= 4 && 5 * common >= 3 * std::max(l.size(), key.size()) && l.compare(0, common, key, 0, common) == 0) {
      best = s;
      ++found;
    }
  }
  return found == 1 ? best : std::string();
}

}  // namespace cellform::core
