// tiltfield (internal): typed access to JSON fields with errors that name the file and the field path.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tiltfield/core/error.hpp"
#include "tiltfield/core/io.hpp"

namespace tf::json_fields {

using nlohmann::json;

inline std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

// A key as a message shows it: an empty key still gets a name.
inline std::string shown_key(const std::string& key) { return key.empty() ? "\"\"" : key; }

inline void require_object(const json& j, const std::string& file, const std::string& field) {
  if (!j.is_object()) throw InputError(file, 0, field, "must be a JSON object");
}

// Refuses keys outside `allowed`, so that a typo does not silently fall back to a default.
inline void only_keys(const json& j, std::initializer_list<const char*> allowed, const std::string& file,
                      const std::string& prefix) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool ok = false;
    for (const char* a : allowed) ok |= it.key() == a;
    if (!ok) throw InputError(file, 0, join(prefix, shown_key(it.key())), "unknown key");
  }
}

inline double number(const json& j, const std::string& file, const std::string& field) {
  if (!j.is_number()) throw InputError(file, 0, field, "must be a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw InputError(file, 0, field, "must be finite");
  return v;
}

inline std::optional<double> optional_number(const json& obj, const char* key, const std::string& file,
                                             const std::string& prefix) {
  if (!obj.contains(key)) return std::nullopt;
  return number(obj.at(key), file, join(prefix, key));
}

inline double number_or(const json& obj, const char* key, double fallback, const std::string& file,
                        const std::string& prefix) {
  return optional_number(obj, key, file, prefix).value_or(fallback);
}

inline double required_number(const json& obj, const char* key, const std::string& file, const std::string& prefix) {
  if (!obj.contains(key)) throw InputError(file, 0, join(prefix, key), "missing");
  return number(obj.at(key), file, join(prefix, key));
}

inline double positive(double v, const std::string& file, const std::string& field) {
  if (!(v > 0.0)) throw InputError(file, 0, field, "must be positive");
  return v;
}

// Positive and at most `max` (in `unit`): a machine value far beyond any machine's (a safe_z of 1e300 mm)
// would be written into the program as a number no reader takes.
inline double positive_at_most(double v, double max, const char* unit, const std::string& file, const std::string& field) {
  positive(v, file, field);
  if (!(v <= max)) {
    std::ostringstream s;
    s << "must be at most " << max << " " << unit;
    throw InputError(file, 0, field, s.str());
  }
  return v;
}

inline std::string string(const json& j, const std::string& file, const std::string& field) {
  if (!j.is_string()) throw InputError(file, 0, field, "must be a string");
  return j.get<std::string>();
}

inline Eigen::Vector3d vec3(const json& j, const std::string& file, const std::string& field) {
  if (!j.is_array() || j.size() != 3) throw InputError(file, 0, field, "must be an array of 3 numbers");
  return {number(j[0], file, field + "[0]"), number(j[1], file, field + "[1]"), number(j[2], file, field + "[2]")};
}

// A length or coordinate, mm, within kMaxCoordinate (1 km) as a path's: beyond it a stock or machine point
// had stopped a command with an internal message or a wrong result (black-box testing).
inline double within_km(double v, const std::string& file, const std::string& field) {
  if (!(std::abs(v) <= kMaxCoordinate)) throw InputError(file, 0, field, "is beyond 1 km: a wrong unit?");
  return v;
}
inline Eigen::Vector3d point_within_km(const json& j, const std::string& file, const std::string& field) {
  const Eigen::Vector3d p = vec3(j, file, field);
  for (int k = 0; k < 3; ++k) within_km(p[k], file, field + "[" + std::to_string(k) + "]");
  return p;
}

// The parser keeps the last of two equal keys in an object, so a scene with "radius" twice would silently
// use one of them; this callback refuses the second, naming the key's path.
class DuplicateKeys {
 public:
  explicit DuplicateKeys(const std::string& file) : file_(file) {}
  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        objects_.push_back({path(), {}});
        break;
      case json::parse_event_t::object_end:
        objects_.pop_back();
        break;
      case json::parse_event_t::key: {
        const std::string key = parsed.get<std::string>();
        auto& keys = objects_.back().keys;
        if (std::find(keys.begin(), keys.end(), key) != keys.end())
          throw InputError(file_, 0, join(objects_.back().path, shown_key(key)), "appears twice in its object");
        keys.push_back(key);
        break;
      }
      default:
        break;
    }
    return true;
  }

 private:
  struct Object {
    std::string path;
    std::vector<std::string> keys;
  };
  // The path of the value being parsed: the enclosing objects' last keys (arrays' indices are not tracked).
  std::string path() const {
    if (objects_.empty() || objects_.back().keys.empty()) return objects_.empty() ? "" : objects_.back().path;
    return join(objects_.back().path, shown_key(objects_.back().keys.back()));
  }
  const std::string& file_;
  std::vector<Object> objects_;
};

// Parses JSON text; a syntax error becomes an InputError naming `file` and the line it is on, and so does a
// key given twice in one object.
inline json parse_text(const std::string& text, const std::string& file) {
  // The parser ends its input at a NUL byte: what followed (a binary file's rest) was never read.
  if (const auto nul = text.find('\0'); nul != std::string::npos)
    throw InputError(file, 1 + static_cast<int>(std::count(text.begin(), text.begin() + long(nul), '\n')), "",
                     "binary data (a NUL byte) in a JSON file");
  try {
    return json::parse(text, DuplicateKeys(file));
  } catch (const json::parse_error& e) {
    int line = 1;
    for (size_t i = 0; i < text.size() && i + 1 < e.byte; ++i) line += text[i] == '\n';
    std::string msg = e.what();
    const auto colon = msg.find("syntax error");
    throw InputError(file, line, "", "invalid JSON: " + (colon == std::string::npos ? msg : msg.substr(colon)));
  } catch (const json::exception& e) {
    // A number too large for a double ("1e400") is an out_of_range error without a position: the line is
    // that of the number it quotes.
    std::string msg = e.what();
    const auto quote = msg.find('\''), end = msg.rfind('\'');
    int line = 0;
    if (quote != std::string::npos && end > quote + 1) {
      const size_t at = text.find(msg.substr(quote + 1, end - quote - 1));
      if (at != std::string::npos) line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + long(at), '\n'));
    }
    const auto tail = msg.find("] ");
    throw InputError(file, line, "", "invalid JSON: " + (tail == std::string::npos ? msg : msg.substr(tail + 2)));
  }
}

// Parses a JSON file; a syntax error becomes an InputError with the line it is on.
inline json parse_file(const std::string& file, const std::string& what) {
  return parse_text(read_text_file(file, what), file);
}

}  // namespace tf::json_fields
