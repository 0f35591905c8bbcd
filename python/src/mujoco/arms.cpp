// coopdyn.MujocoArms: the binding of arms.hpp's OwnedArms (docs/python.md, "The MuJoCo adapter").
#include "arms.hpp"

#include <coopdyn/spatial/pose.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>

namespace coopdyn::python::mujoco {
namespace {

using Vector = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// `value` as a 1-D array of `size` numbers (any dtype numpy converts to float, any strides);
/// else coopdyn.InvalidArgument naming the argument and the expected shape.
Vector checked(const py::handle& value, const char* function, const char* name, Index size)
{
    Vector array = Vector::ensure(value);
    if (!array || array.ndim() != 1 || array.shape(0) != size) {
        PyErr_Clear();
        throw InvalidArgument(function, name, no_arm,
                              "must be an array of shape (" + std::to_string(size) + ",), got " +
                                  py::repr(value).cast<std::string>().substr(0, 80));
    }
    return array;
}

py::array copy(const double* values, Index size)
{
    py::array_t<double> out(size);
    std::copy(values, values + size, out.mutable_data());
    return std::move(out);
}

py::array matrix(const Eigen::MatrixXd& m)
{
    py::array_t<double> out({m.rows(), m.cols()});
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(out.mutable_data(), m.rows(),
                                                                                        m.cols()) = m;
    return std::move(out);
}

Index contact_index(const OwnedArms& self, Index i)
{
    if (i < 0 || i >= self.arms().arms()) {
        throw py::index_error("contact " + std::to_string(i) + " of " + std::to_string(self.arms().arms()));
    }
    return i;
}

void set_state(OwnedArms& self, const py::handle& qpos, const py::handle& qvel)
{
    const mjModel* model = self.model();
    const Vector q = checked(qpos, "MujocoArms.set_state", "qpos", model->nq);
    std::copy(q.data(), q.data() + model->nq, self.data()->qpos);
    if (!qvel.is_none()) {
        const Vector v = checked(qvel, "MujocoArms.set_state", "qvel", model->nv);
        std::copy(v.data(), v.data() + model->nv, self.data()->qvel);
    }
    self.forward();  // mj_forward, and the contact forces it solved for
}

/// An Eigen matrix or vector of the given size that `read` fills, returned as a new numpy array.
template <typename Read> py::array read_matrix(Index rows, Index cols, const Read& read)
{
    Eigen::MatrixXd m(rows, cols);
    read(m);
    return matrix(m);
}
template <typename Read> py::array read_vector(Index size, const Read& read)
{
    Eigen::VectorXd v(size);
    read(v);
    return copy(v.data(), v.size());
}

/// The adapter's reads one at a time, as arrays: for arms that no ControllerInput fits (the
/// controller needs K >= 2 and Q >= 6K; the adapter does not).
void bind_single_reads(py::class_<OwnedArms>& arms)
{
    arms.def("inertia", [](const OwnedArms& self) {
        const Index q = self.arms().joints();
        return read_matrix(q, q, [&](Eigen::MatrixXd& m) { self.arms().read_inertia(self.model(), self.data(), m); });
    }, "M (Q, Q), armature included (C++ read_inertia).");
    arms.def("bias", [](const OwnedArms& self) {
        return read_vector(self.arms().joints(), [&](Eigen::VectorXd& v) { self.arms().read_bias(self.data(), v); });
    }, "h = C qdot + g (Q,): MuJoCo's qfrc_bias, no passive forces (C++ read_bias).");
    arms.def("jacobian", [](const OwnedArms& self) {
        return read_matrix(6 * self.arms().arms(), self.arms().joints(),
                           [&](Eigen::MatrixXd& m) { self.arms().read_jacobian(self.model(), self.data(), m); });
    }, "J (6K, Q): rows 6i..6i+5 map qdot to contact i's [v; w] in {w} (C++ read_jacobian).");
    arms.def("jacobian_rate_qdot", [](const OwnedArms& self) {
        return read_vector(6 * self.arms().arms(), [&](Eigen::VectorXd& v) {
            self.arms().read_jacobian_rate_qdot(self.model(), self.data(), v);
        });
    }, "Jdot qdot (6K,): each contact point's classical acceleration [a; alpha] at zero joint acceleration, "
       "without gravity (C++ read_jacobian_rate_qdot).");
    arms.def("positions", [](const OwnedArms& self) {
        return read_vector(self.arms().joints(), [&](Eigen::VectorXd& v) { self.arms().read_positions(self.data(), v); });
    }, "q (Q,), the chosen joints'.");
    arms.def("velocities", [](const OwnedArms& self) {
        return read_vector(self.arms().joints(), [&](Eigen::VectorXd& v) { self.arms().read_velocities(self.data(), v); });
    }, "qdot (Q,), the chosen joints'.");
}

/// The contacts' frames, the contact points in the object and the object's state.
void bind_contacts(py::class_<OwnedArms>& arms)
{
    arms.def("contact_position",
             [](const OwnedArms& self, Index i) {
                 const Eigen::Vector3d p = self.arms().contact_position(self.data(), contact_index(self, i));
                 return copy(p.data(), 3);
             },
             py::arg("i"), "Contact i's point in {w} (3,).");
    arms.def("contact_rotation",
             [](const OwnedArms& self, Index i) {
                 return matrix(self.arms().contact_rotation(self.data(), contact_index(self, i)));
             },
             py::arg("i"), "Contact i's rotation to {w} (3, 3): columns x, y, z = the inward normal.");
    arms.def("contact_pose",
             [](const OwnedArms& self, Index i) { return self.arms().contact_pose(self.data(), contact_index(self, i)); },
             py::arg("i"), "Contact i's frame in {w} (coopdyn.Pose).");
    arms.def("contact_points",
             [](const OwnedArms& self, const std::string& object_body, const ContactFriction<double>& friction) {
                 return self.arms().contact_points(self.model(), self.data(), object_body, friction);
             },
             py::arg("object_body"), py::arg("friction") = ContactFriction<double>{},
             "ControllerParameters.contacts from the current state: each contact frame in the object's frame.");
    arms.def("object_state",
             [](const OwnedArms& self, const std::string& body) {
                 return mujoco_object_state(self.model(), self.data(), detail::mujoco_body_id(self.model(), body));
             },
             py::arg("body"), "The body's centre-of-mass pose and twist [v; w] (coopdyn.RigidBodyState).");
}

}  // namespace

void bind_arms(py::module_& module)
{
    py::class_<OwnedArms> arms(module, "MujocoArms",
        "K contact points on arms moved by Q hinge or slide joints of a MuJoCo model, read into a ControllerInput "
        "(C++ coopdyn::MujocoArms, docs/adapters.md). Loads the MJCF or URDF file itself (mj_loadXML) and owns "
        "its model and data, at the model's initial state (qpos0, mj_forward).");
    arms.def(py::init([](const std::string& path, const std::vector<std::string>& joints,
                         const std::vector<std::string>& sites, bool sites_only) {
                 return new OwnedArms(path, joints, sites,
                                      sites_only ? MujocoContactFrames::sites_only : MujocoContactFrames::sites_or_bodies);
             }),
             py::arg("model_path"), py::arg("joint_names"), py::arg("contact_sites"), py::arg("sites_only") = false,
             "joint_names: Q joints in q's order; contact_sites: K sites (or bodies: a name no site has is a body's "
             "own frame; sites_only=True refuses them), one per hand, z into the object. Raises "
             "coopdyn.InvalidModel naming the joint or site (docs/adapters.md, \"Construction\").");
    arms.def("contact_frame_kind",
             [](const OwnedArms& self, Index i) {
                 return self.arms().contact_frame_kind(contact_index(self, i)) == MujocoFrameKind::site ? "site" : "body";
             },
             py::arg("i"), "\"site\" or \"body\": what contact i's frame is (a body's own frame, not its surface).");
    arms.def("contact_description",
             [](const OwnedArms& self, Index i) { return self.arms().contact_description(contact_index(self, i)); },
             py::arg("i"), "What contact i's frame is: \"site 'left_palm' on body 'left_link7'\", or \"body ... (no site "
             "has that name: ...)\" naming the body's sites.");
    arms.def_property_readonly("arms", [](const OwnedArms& self) { return self.arms().arms(); }, "K");
    arms.def_property_readonly("joints", [](const OwnedArms& self) { return self.arms().joints(); }, "Q");
    arms.def_property_readonly("nq", [](const OwnedArms& self) { return self.model()->nq; });
    arms.def_property_readonly("nv", [](const OwnedArms& self) { return self.model()->nv; });
    arms.def_property_readonly("time", [](const OwnedArms& self) { return self.data()->time; });
    arms.def_property_readonly("timestep", [](const OwnedArms& self) { return self.model()->opt.timestep; });
    arms.def_property_readonly("qpos", [](const OwnedArms& self) { return copy(self.data()->qpos, self.model()->nq); },
                               "The whole model's qpos (nq,), a copy.");
    arms.def_property_readonly("qvel", [](const OwnedArms& self) { return copy(self.data()->qvel, self.model()->nv); },
                               "The whole model's qvel (nv,), a copy.");
    arms.def("qpos_address", [](const OwnedArms& self, Index j) { return self.arms().qpos_address(j); }, py::arg("j"));
    arms.def("dof_address", [](const OwnedArms& self, Index j) { return self.arms().dof_address(j); }, py::arg("j"));
    arms.def("set_state", &set_state, py::arg("qpos"), py::arg("qvel") = py::none(),
             "The whole model's qpos (nq,) and qvel (nv,; default: unchanged), then mj_forward.");
    arms.def(
        "reset",
        [](OwnedArms& self, const std::string& keyframe) {
            if (keyframe.empty()) {
                mj_resetData(self.model(), self.data());
            } else {
                const int key = mj_name2id(self.model(), mjOBJ_KEY, keyframe.c_str());
                if (key < 0) {
                    throw InvalidArgument("MujocoArms.reset", "keyframe", no_arm, "names no keyframe: '" + keyframe + "'");
                }
                mj_resetDataKeyframe(self.model(), self.data(), key);
            }
            self.forward();
        },
        py::arg("keyframe") = "", "The initial state (qpos0), or the named keyframe's; then mj_forward.");
    arms.def(
        "read",
        [](const OwnedArms& self, InputX& input) {
            self.check(input);
            py::gil_scoped_release release;
            self.arms().read(self.model(), self.data(), input);
        },
        py::arg("input"),
        "Fills input's inertia M, bias h, jacobian J (6K, Q), jacobian_rate_qdot, positions, velocities and the "
        "contacts' poses from the current state (docs/adapters.md, \"What read reads\").");
    arms.def(
        "step",
        [](const OwnedArms& self, const py::handle& tau) {
            const Vector torque = checked(tau, "MujocoArms.step", "tau", self.arms().joints());
            const Eigen::Map<const Eigen::VectorXd> map(torque.data(), self.arms().joints());
            py::gil_scoped_release release;
            self.step(map);
        },
        py::arg("tau"),
        "Applies tau (Q,) to the chosen joints (qfrc_applied) for one MuJoCo step (mj_step2, then mj_step1 of "
        "the next: read() sees the new state).");
    bind_single_reads(arms);
    bind_contacts(arms);
}

}  // namespace coopdyn::python::mujoco
