// Bad input gets a clear error naming the field and the value; a failed run
// leaves no output that looks complete.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
namespace fs = std::filesystem;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <class Fn>
std::string error_of(Fn fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(BadInput, ModelParametersNameFieldAndValue) {
  EXPECT_EQ(error_of([] { SimplePendulum(-1.0, 1.0, 9.81); }),
            "SimplePendulum: parameter 'm' must be positive and finite, got -1");
  EXPECT_EQ(error_of([] { SimplePendulum(1.0, 0.0, 9.81); }),
            "SimplePendulum: parameter 'l' must be positive and finite, got 0");
  EXPECT_EQ(error_of([] { DoublePendulum(1.0, kNaN); }),
            "DoublePendulum: parameter 'm2' must be positive and finite, got nan");
  EXPECT_EQ(error_of([] { DoublePendulum(1.0, 1.0, 1.0, 1.0, -9.81); }),
            "DoublePendulum: parameter 'g' must be non-negative and finite, got -9.8100000000000005");
  EXPECT_TRUE(contains(error_of([] { ElasticPendulum(1.0, -3.0); }), "parameter 'k'"));
  EXPECT_TRUE(contains(error_of([] { KeplerPolar(1.0, 0.0); }), "parameter 'k'"));
  EXPECT_TRUE(contains(error_of([] { CartPendulum(0.0); }), "parameter 'M'"));
  EXPECT_TRUE(contains(error_of([] { BeadOnRotatingHoop(1.0, 1.0, kNaN); }), "parameter 'omega' must be finite"));
  EXPECT_TRUE(contains(error_of([] { PendulumChain<3>(1.0, -2.0); }), "parameter 'l'"));
  EXPECT_EQ(error_of([] { require_in_range("Ball", "e", 1.5, 0.0, 1.0); }),
            "Ball: parameter 'e' must be in [0, 1], got 1.5");
}

SimulationOptions valid() {
  SimulationOptions o;
  o.t_end = 1.0;
  return o;
}

State<1> at_rest(double theta) {
  State<1> s;
  s.q[0] = theta;
  return s;
}

TEST(BadInput, OptionsNameFieldAndValue) {
  const SimplePendulum m;
  auto run = [&](SimulationOptions o) { return error_of([&] { simulate(m, at_rest(0.1), o); }); };
  SimulationOptions o = valid();
  o.t_end = -1.0;
  EXPECT_EQ(run(o), "simulation option 't_end' must be greater than t0 = 0, got -1");
  o = valid();
  o.t_end = 0.0;
  EXPECT_EQ(run(o), "simulation option 't_end' must be greater than t0 = 0, got 0");
  o = valid();
  o.rtol = 0.0;
  EXPECT_EQ(run(o), "simulation option 'rtol' must be > 0, got 0");
  o = valid();
  o.rtol = 1e-30;  // below what a double-precision step can meet: refused at once, not after max_steps
  EXPECT_EQ(run(o),
            "simulation option 'rtol' must be at least 1e-15 (no double-precision step can meet a smaller relative "
            "tolerance), got 1e-30");
  o = valid();
  o.atol = -1e-9;
  EXPECT_EQ(run(o), "simulation option 'atol' must be > 0, got -1e-09");
  o = valid();
  o.dt = kNaN;
  EXPECT_EQ(run(o), "simulation option 'dt' must be finite, got nan");
  o = valid();
  o.t0 = std::numeric_limits<double>::infinity();
  EXPECT_EQ(run(o), "simulation option 't0' must be finite, got inf");
  // A method is a Method; its name is read where text comes in (scene files,
  // the command line) by parse_method(), which names the field it read.
  try {
    parse_method("euler", "run.method");
    ADD_FAILURE() << "no error";
  } catch (const OptionError& e) {
    EXPECT_STREQ(e.what(),
                 "run.method: unknown stepper 'euler' (the steppers are: rk4, dopri5, cash_karp54, fehlberg78, "
                 "bulirsch_stoer, gauss_radau15, rosenbrock4, variational, symplectic_rkn_sb3a_mclachlan, "
                 "velocity_verlet)");
  }
  EXPECT_EQ(parse_method("gauss_radau15", "run.method"), Method::gauss_radau15);
  o = valid();
  o.method = static_cast<Method>(99);
  EXPECT_EQ(run(o), "simulation option 'method' must be one of the Method enumerators, got 99");
  o = valid();
  o.max_steps = 0;
  EXPECT_EQ(run(o), "simulation option 'max_steps' must be at least 1, got 0");
}

/// A model without name() is reported by its C++ type's name, not as "model".
struct UnnamedSpring {
  static constexpr int coordinate_count = 1;
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return 0.5 * q[0] * q[0];
  }
};

TEST(Reports, AModelWithoutANameIsCalledByItsTypeName) {
  State<1> s;
  s.q[0] = 0.1;
  SimulationOptions o = valid();
  o.t_end = 1.0;
  const RunReport r = simulate(UnnamedSpring{}, s, o);
  EXPECT_EQ(r.model, "UnnamedSpring");
  EXPECT_NE(r.summary().find("model UnnamedSpring (1 coordinates)"), std::string::npos) << r.summary();
  EXPECT_EQ(model_name(PendulumChain<3>{}), "pendulum_chain_3");  // a model's own name() is kept
}

TEST(BadInput, NonFiniteInitialStateIsRejected) {
  const DoublePendulum m;
  State<2> s;
  s.qd[1] = kNaN;
  EXPECT_EQ(error_of([&] { simulate(m, s, valid()); }), "initial state: qd[1] ('theta2') is nan; it must be finite");
}

TEST(BadInput, SingularMassMatrixNamesTheState) {
  // The spherical pendulum's M = diag(m l², m l² sin²θ) is singular at the pole θ = 0.
  const SphericalPendulum m;
  State<2> s;
  s.q << 0.0, 0.3;
  const std::string e = error_of([&] { simulate(m, s, valid()); });
  EXPECT_TRUE(contains(e, "mass matrix M = d2L/dqd2 is singular or not positive definite at t = 0, q = [0, 0.2999"))
      << e;
  EXPECT_THROW(accelerations(m, s.q, s.qd), DynamicsError);
  // A Lagrangian with a negative kinetic term is not positive definite.
  const auto bad = make_model<1>(
      "negative_mass", {"x"}, [](const auto&, const auto& qd, const auto&) { return -0.5 * qd[0] * qd[0]; },
      [](const auto& q, const auto&) { return 0 * q[0]; });
  EXPECT_THROW(accelerations(bad, Vec<double, 1>(0.0), Vec<double, 1>(1.0)), DynamicsError);
}

// An ideal pulley of radius r whose angle φ the rope ties to the hanging
// mass's height, x = r φ: φ carries no kinetic energy, M = diag(m, 0).
struct MasslessPulley {
  static constexpr int coordinate_count = 2;
  double m = 1.0, g = 9.81, r = 0.1;
  std::string name() const { return "massless_pulley"; }
  std::array<std::string, 1> holonomic_names() const { return {"rope"}; }
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return m * g * q[0];
  }
  template <class S>
  Vec<S, 1> holonomic(const Vec<S, 2>& q, const S&) const {
    return Vec<S, 1>(q[0] - r * q[1]);
  }
};

TEST(BadInput, AMasslessCoordinateIsNamedAndTheWayOutSaid) {
  State<2> s;
  s.q << 0.2, 2.0;
  const std::string e = error_of([&] { simulate(MasslessPulley{}, s, valid()); });
  EXPECT_TRUE(contains(e, "mass matrix M = d2L/dqd2 is singular")) << e;
  EXPECT_TRUE(contains(e, "coordinate q[1] has no inertia here (row 1 of M is zero)")) << e;
  EXPECT_TRUE(contains(e, "a massless coordinate (an ideal pulley's angle: not supported")) << e;
  EXPECT_FALSE(contains(e, "coordinate q[0] has no inertia")) << e;
}

// V = −√x: the force −∂V/∂x = 1/(2√x) becomes NaN once x < 0.
auto sqrt_well() {
  return make_model<1>(
      "sqrt_well", {"x"}, [](const auto&, const auto& qd, const auto&) { return 0.5 * qd[0] * qd[0]; },
      [](const auto& q, const auto&) {
        using std::sqrt;
        return -sqrt(q[0]);
      });
}

TEST(BadInput, NonFiniteStateMidRunStopsWithTimeAndState) {
  State<1> s;
  s.q[0] = 1.0;
  s.qd[0] = -10.0;  // reaches x = 0 at t ≈ 0.1
  for (const Method method : {Method::dopri5, Method::rk4, Method::cash_karp54, Method::fehlberg78, Method::bulirsch_stoer, Method::gauss_radau15, Method::rosenbrock4}) {
    SimulationOptions o = valid();
    o.method = method;
    try {
      simulate(sqrt_well(), s, o);
      ADD_FAILURE() << method << ": no error";
    } catch (const SimulationError& e) {
      const std::string msg = e.what();
      EXPECT_TRUE(contains(msg, "non-finite state") || contains(msg, "step size underflow") ||
                  contains(msg, "singular or not positive definite"))
          << method << ": " << msg;
      EXPECT_TRUE(contains(msg, "t = ")) << method << ": " << msg;
    }
  }
}

TEST(BadInput, MaxStepsIsAFailureNotATruncation) {
  SimulationOptions o = valid();
  o.max_steps = 10;
  const std::string e = error_of([&] { simulate(SimplePendulum(), at_rest(1.0), o); });
  EXPECT_TRUE(contains(e, "max_steps = 10 reached at t = ")) << e;
}

class OutputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("lagrangian_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(OutputFiles, SuccessfulRunWritesCsvWithHeader) {
  const DoublePendulum m;
  State<2> s;
  s.q << 0.5, -0.5;
  SimulationOptions o = valid();
  o.output_interval = 0.1;
  const auto path = (dir_ / "trajectory.csv").string();
  const RunReport r = simulate(m, s, o, CsvSink(path));
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t [s],theta1 [rad],theta2 [rad],theta1_dot [rad/s],theta2_dot [rad/s],energy [J],total_energy [J]");
  int rows = 0;
  std::string line;
  double last_t = -1;
  while (std::getline(in, line)) {
    ++rows;
    last_t = std::stod(line.substr(0, line.find(',')));
  }
  EXPECT_EQ(rows, 11);
  EXPECT_EQ(static_cast<std::uint64_t>(rows), r.samples);
  EXPECT_DOUBLE_EQ(last_t, 1.0);
  EXPECT_FALSE(fs::exists(path + ".partial"));
}

TEST_F(OutputFiles, FailedRunLeavesNoOutput) {
  State<1> s;
  s.q[0] = 1.0;
  s.qd[0] = -10.0;
  const auto path = (dir_ / "trajectory.csv").string();
  EXPECT_THROW(simulate(sqrt_well(), s, valid(), CsvSink(path)), SimulationError);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
}

TEST_F(OutputFiles, UnwritableDirectoryIsAClearError) {
  const auto path = (dir_ / "no_such_dir" / "trajectory.csv").string();
  const std::string e = error_of([&] { CsvSink sink(path); });
  EXPECT_TRUE(contains(e, "cannot write output file '" + path + ".partial'")) << e;
  RunReport r;
  const std::string e2 = error_of([&] { r.write_json((dir_ / "nope" / "report.json").string()); });
  EXPECT_TRUE(contains(e2, "cannot write report file")) << e2;
}

}  // namespace
