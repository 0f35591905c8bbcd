/// \file
/// \brief Everything in coopdyn: include this, or the individual headers.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/quaternion.hpp"
#include "coopdyn/spatial/skew.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/grasp.hpp"
#include "coopdyn/model/impedance_end_effector.hpp"
#include "coopdyn/model/resolved_acceleration_end_effector.hpp"
#include "coopdyn/model/rigid_object.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/dynamics/energy.hpp"
#include "coopdyn/dynamics/interaction_wrenches.hpp"
#include "coopdyn/dynamics/simulator.hpp"
#include "coopdyn/dynamics/udwadia_kalaba.hpp"
