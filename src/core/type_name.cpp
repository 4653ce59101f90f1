#include <cstdlib>
#include <memory>
#include <string>
#include <typeinfo>

#include <cxxabi.h>

#include "lagrangian/model.hpp"

namespace lagrangian::detail {

std::string type_display_name(const std::type_info& type) {
  int status = 0;
  const std::unique_ptr<char, void (*)(void*)> demangled(abi::__cxa_demangle(type.name(), nullptr, nullptr, &status),
                                                          std::free);
  std::string name = status == 0 && demangled ? demangled.get() : type.name();
  // Drop the namespaces (and enclosing classes) of the outermost name: the
  // last "::" before any template argument list.
  const std::size_t args = name.find('<');
  const std::size_t scope = name.rfind("::", args == std::string::npos ? std::string::npos : args);
  if (scope != std::string::npos) name.erase(0, scope + 2);
  return name;
}

}  // namespace lagrangian::detail
