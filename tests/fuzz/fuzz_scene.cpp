// libFuzzer target for the scene-file reader: any bytes either parse into a
// valid Scene or raise a lagrangian::Error. Anything else (another exception,
// a crash, a sanitizer report, a hang) is a finding.
//
// Invariant also checked: a valid scene with a small gas stays valid once the
// gas is expanded into bodies (validate() predicts every conflict).

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  lagrangian::scene::Scene scene;
  try {
    scene = lagrangian::scene::parse_scene(text, "fuzz.toml");
  } catch (const lagrangian::Error&) {
    return 0;  // rejected with a message: fine
  }
  (void)scene.declared();
  if (scene.gas && scene.gas->count <= 2000) {
    scene.expand_gas();
    try {
      scene.validate();
    } catch (const lagrangian::Error& e) {
      std::fprintf(stderr, "valid scene became invalid after expand_gas(): %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
