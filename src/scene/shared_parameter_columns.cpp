// A scene parameter that sets several of a built-in model's parameters at
// once (one mass for every sphere), and its sensitivity column.

#include "shared_parameter_columns.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace lagrangian::scene::detail {

std::string_view parameter_stem(std::string_view name) {
  while (!name.empty() && name.back() >= '0' && name.back() <= '9') name.remove_suffix(1);
  return name;
}

SharedParameterColumns shared_parameter_columns(const std::vector<std::string>& wanted, const ModelInfo& info,
                                                const std::vector<std::string>& model_parameters) {
  std::vector<std::string> scene_names;
  for (const ParameterInfo& p : info.parameters) scene_names.push_back(p.name);
  lagrangian::detail::parameter_indices(wanted, scene_names);  // OptionError for an unknown or repeated name
  SharedParameterColumns out;
  out.scene = wanted;
  for (const std::string& name : wanted) {
    std::vector<int> columns;
    const auto add = [&](const std::string& model_name) {
      columns.push_back(static_cast<int>(out.model.size()));
      out.model.push_back(model_name);
    };
    if (std::find(model_parameters.begin(), model_parameters.end(), name) != model_parameters.end()) {
      add(name);
    } else {
      for (const std::string& m : model_parameters)
        if (m != name && parameter_stem(m) == name) add(m);
    }
    if (columns.empty())
      throw std::logic_error("built-in model '" + info.name + "': scene parameter '" + name +
                             "' is none of its model's parameters");
    out.sum_of.push_back(std::move(columns));
  }
  return out;
}

SensitivityResult fold_shared_columns(SensitivityResult model_columns, const SharedParameterColumns& columns) {
  const int state = model_columns.state_columns;
  for (Eigen::MatrixXd& s : model_columns.sensitivities) {
    Eigen::MatrixXd folded(s.rows(), state + static_cast<Eigen::Index>(columns.scene.size()));
    folded.leftCols(state) = s.leftCols(state);
    for (std::size_t j = 0; j < columns.scene.size(); ++j) {
      folded.col(state + static_cast<Eigen::Index>(j)).setZero();
      for (int k : columns.sum_of[j]) folded.col(state + static_cast<Eigen::Index>(j)) += s.col(state + k);
    }
    s = std::move(folded);
  }
  model_columns.parameters = columns.scene;
  return model_columns;
}

}  // namespace lagrangian::scene::detail
