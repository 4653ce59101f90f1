#pragma once
/// \file lagrangian.hpp
/// Everything a user needs: models, AD-derived dynamics, constraints and
/// contacts, simulation, sinks, and the analyses (equilibria, small
/// oscillations, boundary-value problems).

#include "lagrangian/ad.hpp"
#include "lagrangian/analysis/analysis.hpp"
#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/mechanics/impact.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/params.hpp"
#include "lagrangian/integrate/method.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/integrate/simulate.hpp"
