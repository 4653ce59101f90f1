// A JSON object written field by field (json_object.hpp).

#include "json_object.hpp"

#include <cmath>
#include <sstream>

#include "lagrangian/detail/text_output.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::scene::detail {

void JsonObject::key(const std::string& k) {
  std::ostringstream os;
  if (!body_.empty()) os << ", ";
  lagrangian::detail::json_string(os, k);
  os << ": ";
  body_ += os.str();
}

void JsonObject::string(const std::string& k, const std::string& value) {
  key(k);
  std::ostringstream os;
  lagrangian::detail::json_string(os, value);
  body_ += os.str();
}

void JsonObject::number(const std::string& k, double value) {
  key(k);
  body_ += std::isfinite(value) ? lagrangian::detail::format_number(value) : std::string("null");
}

void JsonObject::integer(const std::string& k, long long value) {
  key(k);
  body_ += std::to_string(value);
}

void JsonObject::boolean(const std::string& k, bool value) {
  key(k);
  body_ += value ? "true" : "false";
}

void JsonObject::raw(const std::string& k, const std::string& json) {
  key(k);
  body_ += json;
}

std::string json_array(const std::vector<std::string>& items) {
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out + "]";
}

std::string json_strings(const std::vector<std::string>& items) {
  std::vector<std::string> quoted;
  for (const std::string& s : items) {
    std::ostringstream os;
    lagrangian::detail::json_string(os, s);
    quoted.push_back(os.str());
  }
  return json_array(quoted);
}

std::string json_numbers(const double* v, int n) {
  std::vector<std::string> items;
  for (int i = 0; i < n; ++i)
    items.push_back(std::isfinite(v[i]) ? lagrangian::detail::format_number(v[i]) : std::string("null"));
  return json_array(items);
}

}  // namespace lagrangian::scene::detail
