#pragma once
// The options of a subcommand as the subcommand declares them. The parser
// (CLI11) is compiled only where the application is built (main.cpp): being
// header-only, it costs about 5 s of compile time in every file that
// includes it, so the subcommands' own files do not.

#include <optional>
#include <string>
#include <vector>

namespace lagrangian::cli {

/// Where a subcommand declares its arguments; each call binds a variable of
/// the subcommand that parsing then sets. `names` as CLI11 takes them:
/// "--out", "-q,--quiet"; a positional argument has a bare name.
class OptionList {
 public:
  virtual ~OptionList() = default;
  /// A positional argument.
  virtual void positional(const std::string& name, std::string& value, const std::string& help, bool required) = 0;
  /// An option taking one value; `required` options must be given.
  virtual void value(const std::string& names, std::string& v, const std::string& help, bool required = false) = 0;
  virtual void value(const std::string& names, std::optional<std::string>& v, const std::string& help) = 0;
  virtual void value(const std::string& names, std::optional<double>& v, const std::string& help) = 0;
  virtual void value(const std::string& names, std::optional<int>& v, const std::string& help) = 0;
  virtual void value(const std::string& names, double& v, const std::string& help) = 0;
  virtual void value(const std::string& names, int& v, const std::string& help) = 0;
  /// A repeatable option, each value appended.
  virtual void values(const std::string& names, std::vector<std::string>& v, const std::string& help) = 0;
  /// A flag.
  virtual void flag(const std::string& names, bool& v, const std::string& help) = 0;
};

}  // namespace lagrangian::cli
