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

/// \brief The object's pose from a contact frame's pose in {w} and that frame in the object (as
/// contact_frame_in_object returns it): the inverse of contact_frame_in_object, q_o = q_c q_rel^-1,
/// p_o = p_c - R_o p_rel. While the grasp is rigid, each contact predicts the object's pose this
/// way (the controller's dropout prediction and slip, docs/control.md, "Faults").
template <typename Scalar>
Pose<Scalar> object_pose_from_contact(const Pose<Scalar>& contact, const Pose<Scalar>& contact_in_object) noexcept
{
    Pose<Scalar> object;
    object.orientation = (contact.orientation * contact_in_object.orientation.conjugate()).normalized();
    object.position = contact.position - object.orientation * contact_in_object.position;
    return object;
}

}  // namespace coopdyn
