#pragma once
// That each of a model's parameter names reaches its own value through
// parameter_members() (analysis/sensitivity.hpp): for models whose
// parameters are held in arrays and reached by generated accessors.

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "lagrangian/analysis/sensitivity.hpp"

namespace lagrangian::testing {

/// parameter_names_of<M>() is the names of `expected`, in order, and each
/// parameter_members() entry reads its value from `model`.
template <class M>
void expect_parameters_named(const M& model, const std::vector<std::pair<std::string, double>>& expected) {
  const std::vector<std::string> names = parameter_names_of<M>();
  constexpr auto members = M::parameter_members();
  ASSERT_EQ(names.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(names[i], expected[i].first);
    EXPECT_EQ(detail::parameter_of(model, members[i]), expected[i].second) << names[i];
  }
}

}  // namespace lagrangian::testing
