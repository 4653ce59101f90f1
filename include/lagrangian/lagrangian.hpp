#pragma once
/// \file lagrangian.hpp
/// Everything a user needs: models, AD-derived dynamics, constraints and
/// contacts, simulation, sinks, and the analyses (equilibria, small
/// oscillations, boundary-value problems).

#include "lagrangian/ad.hpp"
#include "lagrangian/analysis.hpp"
#include "lagrangian/constraints.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/impact.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/observers.hpp"
#include "lagrangian/params.hpp"
#include "lagrangian/method.hpp"
#include "lagrangian/report.hpp"
#include "lagrangian/simulate.hpp"
