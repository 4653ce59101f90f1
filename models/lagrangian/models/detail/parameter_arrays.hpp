#pragma once
// Parameters held in std::array members (one mass, radius or length per
// body), offered to parameter sensitivities (analysis/sensitivity.hpp) as
// accessors P& (*)(Model&), one per element, and named by body: m1 … mN.

#include <array>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>

namespace lagrangian::models::detail {

/// The accessors of the elements 0 … N−1 of the array member `Array`.
template <class Model, class P, std::size_t N, std::array<P, N> Model::*Array, std::size_t... I>
constexpr std::array<P& (*)(Model&), N> element_accessors(std::index_sequence<I...>) {
  return {+[](Model& model) -> P& { return (model.*Array)[I]; }...};
}

/// The accessor of the scalar member `Member`.
template <class Model, class P, P Model::*Member>
constexpr P& member_accessor(Model& model) {
  return model.*Member;
}

/// The accessors of each array member's elements in turn, then `scalars`
/// (member_accessor<…>).
template <class Model, class P, std::size_t N, std::array<P, N> Model::*... Arrays, class... Scalars>
constexpr auto array_then_scalar_accessors(Scalars... scalars) {
  std::array<P& (*)(Model&), N * sizeof...(Arrays) + sizeof...(Scalars)> out{};
  std::size_t k = 0;
  for (const auto& part : {element_accessors<Model, P, N, Arrays>(std::make_index_sequence<N>{})...})
    for (auto* accessor : part) out[k++] = accessor;
  ((out[k++] = scalars), ...);
  return out;
}

/// The name of parameter `i` of a model whose first parameters are arrays of
/// N elements named `stems` (stem + body number, from 1) and whose others are
/// `scalars`: ("m", "r"), ("e") give m1 … mN, r1 … rN, e.
template <std::size_t N, std::size_t A, std::size_t S>
std::string indexed_parameter_name(std::size_t i, const std::array<std::string_view, A>& stems,
                                   const std::array<std::string_view, S>& scalars) {
  if (i < N * A) return std::string(stems[i / N]) + std::to_string(i % N + 1);
  return std::string(scalars[i - N * A]);
}

}  // namespace lagrangian::models::detail
