#include "output_manifest.hpp"

#include <filesystem>
#include <fstream>

namespace lagrangian::scene::detail {

namespace fs = std::filesystem;

namespace {
constexpr const char* kManifest = ".lagrangian-outputs";

bool plain_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos;
}
}  // namespace

void remove_listed_outputs(const std::string& dir, const std::vector<std::string>& fixed) {
  std::error_code ec;
  for (const std::string& name : fixed) {
    if (!plain_name(name)) continue;
    fs::remove(fs::path(dir) / name, ec);
    fs::remove(fs::path(dir) / (name + ".partial"), ec);
  }
  const fs::path manifest = fs::path(dir) / kManifest;
  {
    std::ifstream in(manifest);
    std::string name;
    while (std::getline(in, name))
      if (plain_name(name)) fs::remove(fs::path(dir) / name, ec);
  }
  fs::remove(manifest, ec);
}

void write_output_manifest(const std::string& dir, const std::vector<std::string>& files) {
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(dir, ec);
  if (ec) return;
  std::ofstream out(fs::path(dir) / kManifest);
  for (const std::string& f : files) {
    const fs::path p = fs::weakly_canonical(f, ec);
    if (!ec && p.parent_path() == root) out << p.filename().string() << "\n";
  }
}

}  // namespace lagrangian::scene::detail
