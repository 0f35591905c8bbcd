/// \file
/// \brief The per-tick core of coopdyn: spatial algebra, the cooperative Model/Data, the
/// interaction dynamics, input checks, the simulator and the coordination (load distribution,
/// coordinated setpoints). What a 1 kHz controller includes: a file that includes it compiles in
/// about 1/20 of the time of one that includes coopdyn.hpp (README, "Headers").
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/errors.hpp"
#include "coopdyn/spatial/inertia.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/quaternion.hpp"
#include "coopdyn/spatial/skew.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"
#include "coopdyn/spatial/symmetric3.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/grasp.hpp"
#include "coopdyn/model/grasp_inverse.hpp"
#include "coopdyn/model/impedance_end_effector.hpp"
#include "coopdyn/model/resolved_acceleration_end_effector.hpp"
#include "coopdyn/model/rigid_object.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/dynamics/energy.hpp"
#include "coopdyn/dynamics/input_check.hpp"
#include "coopdyn/dynamics/interaction_wrenches.hpp"
#include "coopdyn/dynamics/joint_space_grasp.hpp"
#include "coopdyn/dynamics/simulator.hpp"
#include "coopdyn/dynamics/udwadia_kalaba.hpp"
#include "coopdyn/coordination/kinematic_coordination.hpp"
#include "coopdyn/coordination/load_distribution.hpp"
#include "coopdyn/coordination/grasp_squeeze.hpp"
