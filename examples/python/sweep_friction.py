#!/usr/bin/env python3
"""Sweep the contacts' friction coefficient of Lin et al.'s controller and plot the squeeze.

Two free 6-DOF hands (J = I, 2 kg each, the README's controller example) hold a box of mass m at
rest between their palms. For each friction coefficient mu and box mass, one controller tick gives
the palms' normal forces: the least squeeze that friction allows (docs/control.md, "The least
squeeze"), m g / (2 mu) per palm when nothing else loads the contacts. The plot shows coopdyn's
normal force against that line; the tightest friction margin is returned too (zero to rounding:
the least squeeze sits on the friction pyramid's boundary).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/sweep_friction.py [--output out/python]

Needs matplotlib (Debian: python3-matplotlib). docs/python.md, "A parameter sweep".
"""

import argparse
import pathlib

import numpy as np

import coopdyn

GRAVITY = 9.81
STIFFNESS = 1000.0


def palms(mu):
    parameters = coopdyn.ControllerParameters()
    parameters.joints = 12
    s = np.sqrt(0.5)
    contacts = []
    for x, orientation in ((-0.15, [s, 0, s, 0]), (0.15, [0, -s, 0, s])):
        contact = coopdyn.ContactPoint()
        contact.frame = coopdyn.Pose([x, 0, 0], orientation)  # z: the inward normal, x: up
        contact.friction.friction_coefficient = mu
        contacts.append(contact)
    parameters.contacts = contacts
    parameters.stiffness = STIFFNESS * np.eye(6)
    parameters.damping = 100.0 * np.eye(6)
    parameters.posture_stiffness = parameters.posture_damping = np.zeros(12)
    return parameters


def hold(mu, box_mass):
    """One tick holding a box of box_mass at rest: (normal force per palm, tightest margin, status)."""
    model = coopdyn.ControllerModel(palms(mu))
    data = coopdyn.ControllerData(model)
    inp = coopdyn.ControllerInput(model)
    inp.inertia = 2.0 * np.eye(12)
    inp.bias = np.r_[0, 0, 2 * GRAVITY, 0, 0, 0, 0, 0, 2 * GRAVITY, 0, 0, 0]
    inp.jacobian = np.eye(12)
    # The box sags until the impedance carries its weight: F_x = K dz = m g (the estimate L(7)).
    inp.object.pose.position = [0, 0, -box_mass * GRAVITY / STIFFNESS]
    coopdyn.controller_tick(model, data, inp)
    return data.contact_frame_wrenches[2].mean(), data.tightest_force_margin, data.status


def sweep(mus, masses):
    forces = np.zeros((len(masses), len(mus)))
    margins = np.zeros_like(forces)
    for i, m in enumerate(masses):
        for j, mu in enumerate(mus):
            force, margin, status = hold(mu, m)
            assert status == coopdyn.ControlStatus.ok, status
            forces[i, j], margins[i, j] = force, margin
    return forces, margins


def plot(mus, masses, forces, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(6, 4))
    for i, m in enumerate(masses):
        line, = axes.plot(mus, forces[i], "o", label=f"coopdyn, {m:g} kg")
        axes.plot(mus, m * GRAVITY / (2 * mus), "-", color=line.get_color(), alpha=0.5, label=f"m g / (2 mu), {m:g} kg")
    axes.set(xlabel="friction coefficient mu", ylabel="normal force per palm [N]", title="The least squeeze")
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default="out/python", help="directory of the plot (created)")
    arguments = parser.parse_args(argv)
    mus = np.linspace(0.2, 1.0, 9)
    masses = (0.5, 2.0, 4.0)
    forces, margins = sweep(mus, masses)
    output = pathlib.Path(arguments.output)
    output.mkdir(parents=True, exist_ok=True)
    path = output / "sweep_friction.png"
    plot(mus, masses, forces, path)
    print(f"{'mu':>5} " + " ".join(f"{m:>8g} kg" for m in masses) + "   (normal force per palm, N)")
    for j, mu in enumerate(mus):
        print(f"{mu:5.2f} " + " ".join(f"{forces[i, j]:11.3f}" for i in range(len(masses))))
    print(f"tightest force margin over the sweep: {margins.min():.3g} N")
    print(f"wrote {path}")
    return forces, margins


if __name__ == "__main__":
    main()
