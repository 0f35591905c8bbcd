#!/usr/bin/env python3
"""Sweep the controller's friction coefficient in the dual-arm box experiment and plot the squeeze.

Runs coopdyn.experiments.box (the program dual_arm_box's C++ code, docs/python.md "The experiments")
once per friction coefficient mu of the controller's friction model (the plant's stays the
scenario's, 0.5) and plots the palms' normal force over time: the QP's (predicted) and the plant's
(measured) on the left palm. A smaller mu makes the controller squeeze harder for the same load
(docs/control.md, "The least squeeze"); the summary's peak and rest forces are printed per mu.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/sweep_box_friction.py \\
        [--scenario push] [--plant rigid] [--duration 4] [--output out/python]

Needs coopdyn built with its experiments (MuJoCo, nlohmann-json) and matplotlib (Debian:
python3-matplotlib).
"""

import argparse
import pathlib

import coopdyn


def sweep(mus, scenario="push", plant="rigid", duration=4.0):
    """{mu: ExperimentResult} of the scenario with the controller's friction coefficient mu."""
    return {mu: coopdyn.experiments.box(scenario, plant=plant, duration=duration, friction=mu) for mu in mus}


def plot(runs, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(7, 4))
    for mu, (log, _) in runs.items():
        line, = axes.plot(log["time"], log["left_pred_fz"], label=f"mu = {mu:g}, QP")
        axes.plot(log["time"], log["left_meas_fz"], ":", color=line.get_color(), label=f"mu = {mu:g}, measured")
    axes.set(xlabel="time [s]", ylabel="left palm normal force [N]", title=title)
    axes.legend(fontsize=7, ncol=2)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="push", help="a shipped scenario's name or a scenario file")
    parser.add_argument("--plant", default="rigid", choices=("rigid", "mujoco"))
    parser.add_argument("--duration", type=float, default=4.0, help="simulated seconds per run")
    parser.add_argument("--mu", type=float, nargs="+", default=[0.2, 0.35, 0.5, 1.0],
                        help="the controller's friction coefficients")
    parser.add_argument("--output", default="out/python", help="directory of the plot (created)")
    arguments = parser.parse_args(argv)
    runs = sweep(arguments.mu, arguments.scenario, arguments.plant, arguments.duration)
    output = pathlib.Path(arguments.output)
    output.mkdir(parents=True, exist_ok=True)
    path = output / f"sweep_box_friction_{arguments.plant}.png"
    plot(runs, path, f"{arguments.scenario} on the {arguments.plant} plant")
    print(f"{'mu':>5} {'rest N':>8} {'peak N':>8} {'slip mm':>8} {'dropped':>8}   (predicted normal force per palm)")
    for mu, (_, summary) in runs.items():
        print(f"{mu:5.2f} {summary['rest_normal_predicted']:8.1f} {summary['peak_normal_predicted']:8.1f} "
              f"{1e3 * summary['max_slip']:8.3f} {str(summary['dropped']):>8}")
    print(f"wrote {path}")
    return runs


if __name__ == "__main__":
    main()
