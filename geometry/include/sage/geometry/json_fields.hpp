#pragma once
// Typed access to the fields of a JSON input file (a CSG model, a problem
// file), with messages that name the file and the JSON pointer of the
// field: "model.json: at /field/args/0/radius: must be positive".
// Readers derive from JsonFields<TheirError>.

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <initializer_list>
#include <set>
#include <string>

namespace sage::geometry {

using Json = nlohmann::json;

template <class Error>
class JsonFields {
 public:
  explicit JsonFields(std::string source) : source_(std::move(source)) {}

  /// Throws Error("SOURCE: at POINTER: MESSAGE").
  [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
    throw Error(source_ + ": at " + (pointer.empty() ? "/" : pointer) + ": " + message);
  }

  /// Fails at the first key of the object `j` (at `at`) not in `keys`, listing those allowed.
  void allow_keys(const Json& j, const std::string& at, const std::set<std::string>& keys) const {
    for (const auto& [key, value] : j.items())
      if (!keys.count(key)) {
        std::string list;
        for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
        fail(at + "/" + key, "unknown key \"" + key + "\" here (allowed: " + list + ")");
      }
  }

  /// A finite number.
  double number(const Json& j, const std::string& at) const {
    if (!j.is_number()) fail(at, "expected a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(at, "number is not finite");
    return v;
  }
  double number_at(const Json& j, const char* key, const std::string& at) const {
    if (!j.contains(key)) fail(at, std::string("missing \"") + key + "\"");
    return number(j[key], at + "/" + key);
  }
  std::string string_at(const Json& j, const char* key, const std::string& at) const {
    if (!j[key].is_string()) fail(at + "/" + key, "expected a string");
    return j[key].get<std::string>();
  }
  /// An array of n numbers (the rest of the result 0).
  std::array<double, 3> point(const Json& v, const std::string& at, int n) const {
    if (!v.is_array() || static_cast<int>(v.size()) != n)
      fail(at, "expected an array of " + std::to_string(n) + " numbers");
    std::array<double, 3> r{0, 0, 0};
    for (int i = 0; i < n; ++i)
      r[static_cast<std::size_t>(i)] = number(v[static_cast<std::size_t>(i)], at + "/" + std::to_string(i));
    return r;
  }

 private:
  std::string source_;
};

}  // namespace sage::geometry
