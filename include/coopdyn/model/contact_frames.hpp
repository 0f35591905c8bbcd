/// \file
/// \brief A contact frame in the object's body frame, from both frames' poses in {w}: what
/// ContactPoint::frame holds (control/controller_model.hpp). docs/adapters.md, "Contact points".
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/spatial/pose.hpp"

#include <cstdio>
#include <string>

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

/// \brief The cosine of the angle between a contact frame's z axis (the object's inward surface
/// normal at the contact) and its position r_i from the object's centre: z_i . r_i / |r_i|, for a
/// frame in the object (ContactPoint::frame, contact_frame_in_object); 0 when r_i = 0. Negative
/// when the normal points into the object, towards the centre's side of the contact's tangent
/// plane: true at every point of a convex object's surface, whatever the patch's offset from the
/// face's centre. Zero (z tangential) or positive (z outward) is a frame facing the wrong way: the
/// friction rows would bound a pulling or sliding force (docs/control.md, "Contact frames").
template <typename Scalar> Scalar contact_normal_cosine(const Pose<Scalar>& frame_in_object) noexcept
{
    using std::sqrt;
    const Scalar length = sqrt(frame_in_object.position.squaredNorm());
    if (!(length > Scalar(0))) {
        return Scalar(0);
    }
    return (frame_in_object.orientation * Vector3<Scalar>::UnitZ()).dot(frame_in_object.position) / length;
}

/// A contact's normal counts as tangential within this cosine (about 0.00006 degrees), so that a
/// tangential z refused exactly is refused whatever the rounding of its frame.
constexpr double contact_normal_tolerance = 1e-6;

/// \brief Why a contact frame in the object (as for contact_normal_cosine) does not face into the
/// object, or "" when it does: z . r >= -contact_normal_tolerance |r|, with z and r in the message
/// and the fixes. One text for every door that takes contact frames (ControllerModel, the scene
/// files).
template <typename Scalar> std::string contact_normal_problem(const Pose<Scalar>& frame_in_object)
{
    const double cosine = detail::value_of(contact_normal_cosine(frame_in_object));
    if (cosine < -contact_normal_tolerance) {
        return {};
    }
    const auto text = [](const auto& v) {
        char buffer[96];
        std::snprintf(buffer, sizeof buffer, "(%.4g, %.4g, %.4g)", detail::value_of(v(0)), detail::value_of(v(1)),
                      detail::value_of(v(2)));
        return std::string(buffer);
    };
    char value[32];
    std::snprintf(value, sizeof value, "%.3g", cosine);
    return "the contact normal z = " + text(frame_in_object.orientation * Vector3<Scalar>::UnitZ()) +
           (cosine > contact_normal_tolerance ? " points out of the object" : " lies along the object's surface") +
           " (z . r / |r| = " + value + ", must be negative, for the contact at r = " + text(frame_in_object.position) +
           " from the object's centre); z must be the object's inward surface normal: turn the frame "
           "(e.g. by pi about its x axis), or, for a grasp where the inward normal need not face the "
           "centre, set check_contact_normals = false";
}

}  // namespace coopdyn
