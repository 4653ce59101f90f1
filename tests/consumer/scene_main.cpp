// Built against the installed package: a scene from TOML text, run with the
// scene library (lagrangian::scene), against the closed form of a projectile.
#include <cmath>
#include <cstdio>

#include <lagrangian/scene/io.hpp>
#include <lagrangian/scene/run.hpp>

int main() {
  const auto scene = lagrangian::scene::parse_scene(R"(
name = "throw"
[run]
t_end = 1.0
[output]
trajectory = false
plots = false
[[bodies]]
name = "ball"
mass = 0.2
velocity = [3.0, 0.0, 4.0]
[gravity]
g = [0.0, 0.0, -9.81]
)",
                                                    "consumer.toml");
  lagrangian::scene::RunControls controls;
  controls.write_outputs = false;
  const auto r = lagrangian::scene::run(scene, controls);
  const double z = r.q_final[2], expected = 4.0 - 0.5 * 9.81;
  std::printf("scene ball z after 1 s: %.12g (closed form %.12g)\n", z, expected);
  return std::abs(z - expected) < 1e-10 ? 0 : 1;
}
