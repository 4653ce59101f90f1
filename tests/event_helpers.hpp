#pragma once
// Shared by the event tests.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/impacts.hpp"

namespace lagrangian_test {

/// Located event times against closed forms (s).
constexpr double kEventTime = 1e-12;

/// A ball at rest with its centre at height z.
inline lagrangian::State<3> dropped(double z) {
  lagrangian::State<3> s;
  s.q << 0.0, 0.0, z;
  s.qd.setZero();
  return s;
}

}  // namespace lagrangian_test
