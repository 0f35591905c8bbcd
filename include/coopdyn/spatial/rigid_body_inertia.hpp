/// \file
/// \brief Rigid-body spatial inertias: CentralInertia (diag(m I3, I_c) about the centre of mass)
/// and SpatialInertia (a rigid body's, or any diag(m I3, J) seen from another point), with the
/// operations the cooperative model is built from: the shift G_i M_i G_i^T of (31), sums, rotation
/// into {w} (9), and a structured solve. The general symmetric 6x6 is ArticulatedInertia
/// (articulated_inertia.hpp); coopdyn/spatial/inertia.hpp includes both.
///
/// Both act on motions [v; w] and give forces [f; t] (docs/conventions.md), torques about the
/// reference point. Fixed-size, Scalar-generic, allocation-free.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/numerics/fixed_ldlt.hpp"
#include "coopdyn/spatial/skew.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"
#include "coopdyn/spatial/symmetric3.hpp"

namespace coopdyn {

template <typename ScalarType> class SpatialInertia;

/// \brief Inertia of a body about its own centre of mass, diag(m I3, I_c): the end-effector
/// inertia diag(m_i I3, J_i) of (1) and the object's diag(m_o I3, J_o) of (9).
///
/// The type is the fast path of the interaction solver: a central inertia has no first moment,
/// so applying, shifting and adding it costs about half of a general SpatialInertia's
/// operations. shifted(r) gives the general SpatialInertia it becomes seen from another point.
template <typename ScalarType> class CentralInertia {
public:
    using Scalar = ScalarType;

    CentralInertia() : mass_(0) {}
    CentralInertia(const Scalar& mass, const Symmetric3<Scalar>& rotational) : mass_(mass), rotational_(rotational) {}
    /// From a dense 3x3 rotational inertia (only its lower triangle is read).
    template <typename Derived>
    CentralInertia(const Scalar& mass, const Eigen::MatrixBase<Derived>& rotational)
        : mass_(mass), rotational_(rotational)
    {
    }

    static CentralInertia Zero() { return CentralInertia(); }

    const Scalar& mass() const noexcept { return mass_; }
    /// I_c, about the centre of mass.
    const Symmetric3<Scalar>& rotational() const noexcept { return rotational_; }

    /// The dense 6x6 matrix diag(m I3, I_c).
    Matrix6<Scalar> matrix() const
    {
        Matrix6<Scalar> result = Matrix6<Scalar>::Zero();
        result.template topLeftCorner<3, 3>().diagonal().setConstant(mass_);
        result.template bottomRightCorner<3, 3>() = rotational_.matrix();
        return result;
    }
    /// M a = [m v; I_c w].
    COOPDYN_INLINE Force<Scalar> operator*(const Motion<Scalar>& motion) const noexcept
    {
        return Force<Scalar>::make(detail::scaled(mass_, motion.linear), rotational_ * motion.angular);
    }
    /// M [a; 0] = [m a; 0], the inertial force of a pure translational acceleration.
    template <typename Derived>
    COOPDYN_INLINE Force<Scalar> apply_translation(const Eigen::MatrixBase<Derived>& a) const noexcept
    {
        return Force<Scalar>::make(detail::scaled(mass_, a), Vector3<Scalar>::Zero());
    }
    /// G(r) M G(r)^T = [[m I3, m S(r)^T], [m S(r), I_c + m S(r) S(r)^T]]: the parallel-axis
    /// theorem, the arm's term of (31) for r = r_i.
    template <typename Derived> SpatialInertia<Scalar> shifted(const Eigen::MatrixBase<Derived>& r) const noexcept;
    /// diag(R, R) M diag(R, R)^T (e.g. J_o = R J_o_body R^T, (9)).
    template <typename Derived> CentralInertia rotated(const Eigen::MatrixBase<Derived>& rotation) const
    {
        return CentralInertia(mass_, rotational_.rotated(rotation));
    }
    /// v = f / m, w = I_c^-1 t (preconditions as SpatialInertia::solve).
    Motion<Scalar> solve(const Force<Scalar>& force) const noexcept
    {
        COOPDYN_ASSERT(mass_ > Scalar(0), "CentralInertia::solve needs a positive mass");
        return Motion<Scalar>::make(detail::scaled(Scalar(1) / mass_, force.linear), rotational_.solve(force.angular));
    }
    Scalar kinetic_energy(const Motion<Scalar>& twist) const noexcept
    {
        return Scalar(0.5) * twist.dot((*this) * twist);
    }
    template <typename Other> CentralInertia<Other> cast() const
    {
        return CentralInertia<Other>(Other(mass_), rotational_.template cast<Other>());
    }

private:
    Scalar mass_;
    Symmetric3<Scalar> rotational_;
};

/// \brief Inertia of a rigid body about a reference point: mass m, first moment h = m c (c the
/// centre of mass relative to the reference point) and rotational inertia I about the reference
/// point, so that
///
///     matrix() = [[m I3, S(h)^T], [S(h), I]],    I = I_c + m S(c) S(c)^T.
///
/// The end-effector inertia diag(m_i I3, J_i) of (1) and the object's diag(m_o I3, J_o) of (9)
/// are the case h = 0; their sum seen from the object, M_o + sum G_i M_i G_i^T of (31), is again
/// one (the composite rigid body).
template <typename ScalarType> class SpatialInertia {
public:
    using Scalar = ScalarType;

    /// Zero inertia.
    SpatialInertia() : mass_(0), first_moment_(Vector3<Scalar>::Zero()) {}
    SpatialInertia(const Scalar& mass, const Vector3<Scalar>& first_moment, const Symmetric3<Scalar>& rotational)
        : mass_(mass), first_moment_(first_moment), rotational_(rotational)
    {
    }
    /// diag(m I3, J): a body about its centre of mass (the paper's M_o (9) and M_i (1)).
    static SpatialInertia block_diagonal(const Scalar& mass, const Symmetric3<Scalar>& rotational)
    {
        return SpatialInertia(mass, Vector3<Scalar>::Zero(), rotational);
    }
    /// diag(m I3, J) from a dense 3x3 J (only its lower triangle is read).
    template <typename Derived>
    static SpatialInertia block_diagonal(const Scalar& mass, const Eigen::MatrixBase<Derived>& rotational)
    {
        return block_diagonal(mass, Symmetric3<Scalar>(rotational));
    }
    /// A body of mass m with centre of mass at c and rotational inertia I_c about c.
    static SpatialInertia from_centre(const Scalar& mass, const Vector3<Scalar>& centre,
                                      const Symmetric3<Scalar>& rotational_about_centre)
    {
        Symmetric3<Scalar> rotational = rotational_about_centre;
        rotational.add_skew_square(mass, centre);
        return SpatialInertia(mass, mass * centre, rotational);
    }
    static SpatialInertia Zero() { return SpatialInertia(); }
    /// A central inertia diag(m I3, I_c) as a spatial inertia about its centre of mass (h = 0).
    SpatialInertia(const CentralInertia<Scalar>& central)  // NOLINT: implicit, a central inertia is one
        : mass_(central.mass()), first_moment_(Vector3<Scalar>::Zero()), rotational_(central.rotational())
    {
    }

    const Scalar& mass() const noexcept { return mass_; }
    /// h = m c.
    const Vector3<Scalar>& first_moment() const noexcept { return first_moment_; }
    /// c = h / m (requires m > 0).
    Vector3<Scalar> centre() const noexcept { return first_moment_ / mass_; }
    /// I, about the reference point.
    const Symmetric3<Scalar>& rotational() const noexcept { return rotational_; }
    /// I_c = I - m S(c) S(c)^T, about the centre of mass (requires m > 0).
    Symmetric3<Scalar> rotational_about_centre() const noexcept
    {
        Symmetric3<Scalar> result = rotational_;
        result.add_skew_square(-Scalar(1) / mass_, first_moment_);
        return result;
    }

    /// The dense 6x6 matrix [[m I3, S(h)^T], [S(h), I]].
    Matrix6<Scalar> matrix() const
    {
        Matrix6<Scalar> result;
        result.template topLeftCorner<3, 3>() = mass_ * Matrix3<Scalar>::Identity();
        result.template bottomLeftCorner<3, 3>() = skew(first_moment_);
        result.template topRightCorner<3, 3>() = skew(first_moment_).transpose();
        result.template bottomRightCorner<3, 3>() = rotational_.matrix();
        return result;
    }

    /// M a: [m v - h x w; h x v + I w].
    Force<Scalar> operator*(const Motion<Scalar>& motion) const noexcept
    {
        return Force<Scalar>::make(mass_ * motion.linear - detail::cross(first_moment_, motion.angular),
                                   detail::cross(first_moment_, motion.linear) + rotational_ * motion.angular);
    }

    /// G(r) M G(r)^T with G(r) = [[I3, 0], [S(r), I3]]: this inertia, attached at the point
    /// displaced by r from the reference point, seen from the reference point (the parallel-axis
    /// theorem). For r = r_i it is the arm's contribution to (31):
    /// h' = h + m r, I' = I + m S(r) S(r)^T + S(h) S(r)^T + S(r) S(h)^T.
    template <typename Derived> SpatialInertia shifted(const Eigen::MatrixBase<Derived>& r) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        SpatialInertia result;
        result.add_shifted(*this, r);
        return result;
    }

    /// this += other.shifted(r), without forming the shifted inertia (the composite inertia's
    /// accumulation on the per-tick path).
    template <typename Derived>
    void add_shifted(const SpatialInertia& other, const Eigen::MatrixBase<Derived>& r_in) noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        // Copies, not references: other may be *this (M.add_shifted(M, r) = M + G M G^T).
        const Vector3<Scalar> r = r_in;
        const Scalar m = other.mass_;
        const Vector3<Scalar> h = other.first_moment_;
        mass_ += m;
        first_moment_ += h + m * r;
        rotational_ += other.rotational_;
        rotational_.add_skew_square(m, r);
        // S(h) S(r)^T + S(r) S(h)^T = 2 (h . r) I3 - h r^T - r h^T
        const Scalar twice_dot = Scalar(2) * h.dot(r);
        rotational_.xx += twice_dot - Scalar(2) * h(0) * r(0);
        rotational_.yy += twice_dot - Scalar(2) * h(1) * r(1);
        rotational_.zz += twice_dot - Scalar(2) * h(2) * r(2);
        rotational_.yx -= h(1) * r(0) + r(1) * h(0);
        rotational_.zx -= h(2) * r(0) + r(2) * h(0);
        rotational_.zy -= h(2) * r(1) + r(2) * h(1);
    }

    /// this += other.shifted(r) for a central inertia: mass, first moment m r and the
    /// parallel-axis term I_c + m S(r) S(r)^T (the fast path of the composite inertia).
    template <typename Derived>
    COOPDYN_INLINE void add_shifted(const CentralInertia<Scalar>& other, const Eigen::MatrixBase<Derived>& r) noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        const Scalar m = other.mass();
        mass_ += m;
        first_moment_(0) += m * r(0);
        first_moment_(1) += m * r(1);
        first_moment_(2) += m * r(2);
        rotational_ += other.rotational();
        rotational_.add_skew_square(m, r);
    }

    /// M [a; 0] = [m a; h x a].
    template <typename Derived> Force<Scalar> apply_translation(const Eigen::MatrixBase<Derived>& a) const noexcept
    {
        return Force<Scalar>::make(mass_ * a, detail::cross(first_moment_, a));
    }

    /// diag(R, R) M diag(R, R)^T: the same inertia in the frame R rotates into (e.g. from the body
    /// frame into {w}, (9)).
    template <typename Derived> SpatialInertia rotated(const Eigen::MatrixBase<Derived>& rotation) const
    {
        return SpatialInertia(mass_, rotation * first_moment_, rotational_.rotated(rotation));
    }

    SpatialInertia& operator+=(const SpatialInertia& other) noexcept
    {
        mass_ += other.mass_;
        first_moment_ += other.first_moment_;
        rotational_ += other.rotational_;
        return *this;
    }
    SpatialInertia& operator-=(const SpatialInertia& other) noexcept
    {
        mass_ -= other.mass_;
        first_moment_ -= other.first_moment_;
        rotational_ -= other.rotational_;
        return *this;
    }
    friend SpatialInertia operator+(SpatialInertia a, const SpatialInertia& b) noexcept { return a += b; }

    /// Solves M a = force in O(1) through the structure: with c = h / m,
    /// w = I_c^-1 (t - c x f) and v = f / m + c x w (I_c = the rotational inertia about the
    /// centre of mass, the Schur complement of m I3). Precondition (asserted in debug builds):
    /// m > 0 and I_c positive definite.
    COOPDYN_INLINE Motion<Scalar> solve(const Force<Scalar>& force) const noexcept
    {
        COOPDYN_ASSERT(mass_ > Scalar(0), "SpatialInertia::solve needs a positive mass");
        // In scalars (see detail::cross): this is the latency-critical step of the tick.
        const Scalar inverse_mass = Scalar(1) / mass_;
        const Vector3<Scalar> centre = detail::scaled(inverse_mass, first_moment_);
        Symmetric3<Scalar> about_centre = rotational_;
        about_centre.add_skew_square(-mass_, centre);
        const Vector3<Scalar> torque_about_centre = detail::cross(centre, force.linear);
        const Vector3<Scalar> angular = about_centre.solve(
            Vector3<Scalar>(force.angular(0) - torque_about_centre(0), force.angular(1) - torque_about_centre(1),
                            force.angular(2) - torque_about_centre(2)));
        const Vector3<Scalar> carried = detail::cross(centre, angular);
        return Motion<Scalar>::make(Vector3<Scalar>(inverse_mass * force.linear(0) + carried(0),
                                                    inverse_mass * force.linear(1) + carried(1),
                                                    inverse_mass * force.linear(2) + carried(2)),
                                    angular);
    }

    /// 1/2 a^T M a, the kinetic energy of the twist a.
    Scalar kinetic_energy(const Motion<Scalar>& twist) const noexcept
    {
        return Scalar(0.5) * twist.dot((*this) * twist);
    }

    template <typename Other> SpatialInertia<Other> cast() const
    {
        return SpatialInertia<Other>(Other(mass_), first_moment_.template cast<Other>(),
                                     rotational_.template cast<Other>());
    }

private:
    Scalar mass_;
    Vector3<Scalar> first_moment_;
    Symmetric3<Scalar> rotational_;
};

template <typename Scalar>
template <typename Derived>
SpatialInertia<Scalar> CentralInertia<Scalar>::shifted(const Eigen::MatrixBase<Derived>& r) const noexcept
{
    SpatialInertia<Scalar> result;
    result.add_shifted(*this, r);
    return result;
}

}  // namespace coopdyn
