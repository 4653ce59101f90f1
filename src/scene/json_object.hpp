#pragma once
// Internal: a JSON object written field by field, for the inspection's JSON
// (lagrangian inspect --json).

#include <string>
#include <vector>

namespace lagrangian::scene::detail {

/// Keys in the order given; values escaped as report.json's are.
class JsonObject {
 public:
  void string(const std::string& key, const std::string& value);
  void number(const std::string& key, double value);  ///< non-finite values as null
  void integer(const std::string& key, long long value);
  void boolean(const std::string& key, bool value);
  void raw(const std::string& key, const std::string& json);  ///< an array or object already written
  std::string str() const { return "{" + body_ + "}"; }

 private:
  void key(const std::string& k);
  std::string body_;
};

std::string json_array(const std::vector<std::string>& items);  ///< items already JSON
std::string json_strings(const std::vector<std::string>& items);
std::string json_numbers(const double* v, int n);  ///< non-finite values as null

}  // namespace lagrangian::scene::detail
