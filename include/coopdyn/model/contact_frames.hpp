/// \file
/// \brief A contact frame in the object's body frame, from both frames' poses in {w}: what
/// ContactPoint::frame holds (control/controller_model.hpp). docs/adapters.md, "Contact points".
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/spatial/pose.hpp"

namespace coopdyn {

/// \brief The contact frame {c_i} relative to the object: position R_o^T (p_c - p_o), the contact
/// point relative to the object's centre in the object's axes, and orientation q_o^-1 q_c. This is
/// the inverse of ContactPoint's r_i = R_o position, R_ci = R_o R(orientation).
/// \param object the object's centre and orientation in {w} (the pose the controller's input
///   object.pose measures).
/// \param contact the contact frame in {w} (z: the object's inward normal).
template <typename Scalar>
Pose<Scalar> contact_frame_in_object(const Pose<Scalar>& object, const Pose<Scalar>& contact) noexcept
{
    const Quaternion<Scalar> inverse = object.orientation.conjugate();
    Pose<Scalar> relative;
    relative.position = inverse * (contact.position - object.position);
    relative.orientation = (inverse * contact.orientation).normalized();
    return relative;
}

}  // namespace coopdyn
