#pragma once
/// \file lagrangian.hpp
/// Everything a user needs: models, AD-derived dynamics, simulation, sinks.

#include "lagrangian/ad.hpp"
#include "lagrangian/constraints.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/impact.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/observers.hpp"
#include "lagrangian/params.hpp"
#include "lagrangian/report.hpp"
#include "lagrangian/simulate.hpp"
