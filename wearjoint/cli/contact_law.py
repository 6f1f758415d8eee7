"""`wearjoint contact-law`: the coefficient of restitution a single impact actually gets under each contact damping
law, against the impact speed (docs/reference/model.md §3.5, :mod:`wearjoint.core.damping`).

The four laws are asked for the same ``--restitution``: Hunt-Crossley gives it exactly at
``--restitution-speed-m-s`` (a slower impact rebounds more, a faster one less), Lankarani-Nikravesh (the paper's
Eq. 15) its own value at every speed (0.913 for 0.9), Tsuji the asked value at every speed (for a body of
``--effective-mass-kg``), Lankarani-Nikravesh exact the asked value at every speed above its velocity floor.  Writes ``contact_law.csv``, ``contact_law.json`` and ``contact_law.png``.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from ..checks import require
from ..parameters import CONTACT_DAMPINGS, JointParameters, SliderCrankParameters
from ..results import write_json_atomic
from ..run_options import option_name
from .options import add_model_arguments, add_output_arguments, given_options, model_from_args

# the laws that multiply the elastic force (Hunt-Crossley, Lankarani-Nikravesh) rebound the same whatever its shape;
# Tsuji's damping reads its secant stiffness, so its row is the point law's, K delta^n (tests/core/test_contact_damping.py
# integrates impacts through the joint under both contact models)
FOUNDATION_NOTE = ("tsuji's row is the point law's (F_e = K delta^n, --contact-model deepest); with the foundation's "
                   "resultant (the default contact) an impact rebounds a little lower as it goes deeper (the paper's "
                   "joint at 0.89 kg: 0.2957 for 0.3 at 1 m/s, 0.8983 for 0.9; docs/reference/model.md §3.5); the "
                   "other laws' rows hold for both")
# the table's (and contact_law.csv's) impact speeds [m/s]: 1 mm/s to 1 m/s
TABLE_SPEEDS_M_S = (1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 0.1, 0.2, 0.5, 1.0)
# the figure's speeds [m/s]: log-spaced over the same range
PLOT_SPEEDS_M_S = np.logspace(-3.0, 0.0, 60)


def column(law: str) -> str:
    """The CSV column of ``law``: ``restitution_hunt_crossley``."""
    return "restitution_" + law.replace("-", "_")


def law_joint(joint: JointParameters, law: str) -> JointParameters:
    """``joint`` with damping law ``law``: the same restitution, restitution speed, effective mass and exponent."""
    return joint if joint.contact_damping == law else dataclasses.replace(joint, contact_damping=law)


def restitution_curves(joint: JointParameters, speeds_m_s) -> dict[str, np.ndarray]:
    """Law -> the restitution [-] of a single impact at each of ``speeds_m_s`` (:meth:`JointParameters.restitution_at`),
    every law asked for ``joint``'s restitution."""
    curves = {}
    for law in CONTACT_DAMPINGS:
        variant = law_joint(joint, law)     # Tsuji's is solved at each speed too (~7 ms each): its constancy is shown
        curves[law] = np.array([variant.restitution_at(float(v)) for v in speeds_m_s])
    return curves


def format_table(joint: JointParameters, speeds_m_s, curves: dict) -> str:
    """One row per law, the joint's marked with ``*``; a column per impact speed [mm/s]."""
    name_width = max(len(law) for law in CONTACT_DAMPINGS)
    lines = ["  " + "impact speed [mm/s]".ljust(name_width) + "".join(f"{v * 1e3:>8g}" for v in speeds_m_s)]
    for law in CONTACT_DAMPINGS:
        mark = "*" if law == joint.contact_damping else " "
        lines.append(f"{mark} {law:<{name_width}}" + "".join(f"{e:>8.4f}" for e in curves[law]))
    return "\n".join(lines)


def plot_contact_law(joint: JointParameters, path: Path) -> None:
    """e(v) of the four laws on a log speed axis, the asked restitution (dashed) and its speed (dotted)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves = restitution_curves(joint, PLOT_SPEEDS_M_S)
    fig, ax = plt.subplots(figsize=(8.5, 4.2))
    for law, marker, style in zip(CONTACT_DAMPINGS, (None, "s", "o", "^"), ("-", "-", "-", "--")):
        given = law == joint.contact_damping
        ax.plot(PLOT_SPEEDS_M_S, curves[law], style, marker=marker, markevery=(3, 6), ms=4,
                lw=2.2 if given else 1.4, zorder=3, label=law + (" (this joint)" if given else ""))
    # the asked restitution wide and light, under the curves: Tsuji's lies on it
    ax.axhline(joint.restitution, color="0.7", ls="--", lw=3.0, zorder=1,
               label=f"asked restitution {joint.restitution:g}")
    ax.axvline(joint.restitution_speed_m_s, color="0.3", ls=":", lw=1.2, zorder=1,
               label=f"restitution speed {joint.restitution_speed_m_s * 1e3:g} mm/s (hunt-crossley)")
    ax.set_xscale("log")
    ax.set_xlim(PLOT_SPEEDS_M_S[0], PLOT_SPEEDS_M_S[-1])
    low = min(float(c.min()) for c in curves.values())
    ax.set_ylim(max(0.0, low - 0.05), 1.01)
    ax.set_xlabel("normal impact speed [m/s]")
    ax.set_ylabel("coefficient of restitution [-]")
    ax.set_title(f"restitution of a single impact, asked {joint.restitution:g} "
                 f"(Tsuji for {joint.effective_mass_kg:g} kg)", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))   # clear of the curves
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def add_arguments(parser) -> None:
    add_output_arguments(parser)
    add_model_arguments(parser)


def tsuji_mass_options(mechanism: SliderCrankParameters) -> list[str]:
    """The mechanism's fields that set the Tsuji damping's effective mass at its clearance joint
    (:attr:`SliderCrankParameters.contact_effective_mass_kg`, the joint's default ``effective_mass_kg``): the masses
    it sums there (each probed at 1 and 2 kg) and the joint's location, which picks them."""
    masses = [f.name for f in dataclasses.fields(SliderCrankParameters) if f.name.endswith("_mass_kg")
              and mechanism.replace(**{f.name: 1.0}).contact_effective_mass_kg
              != mechanism.replace(**{f.name: 2.0}).contact_effective_mass_kg]
    return [*masses, "clearance_joint"]


def check_mechanism_options(args, mechanism: SliderCrankParameters) -> None:
    """A mechanism option given to contact-law, refused in one line unless it sets Tsuji's effective mass (without
    ``--effective-mass-kg``): a single impact runs no mechanism, so the others would change nothing (its curves
    depend on the damping law's options alone; the effective mass is reported, the mass Tsuji's e is exact for)."""
    given = given_options(args, SliderCrankParameters)
    used = [] if args.effective_mass_kg is not None else tsuji_mass_options(mechanism)
    reads = ("of the mechanism it reads only what sets Tsuji's reported effective mass, "
             + ", ".join(map(option_name, used)) if used else "--effective-mass-kg gives Tsuji's reported effective mass")
    for name, value in given.items():
        require(option_name(name), value, name in used,
                f"only with a command that runs the mechanism: contact-law's single impact runs none, and {reads}")


# the joint's fields a single impact's restitution reads: the laws' own, the law marked, the exponent (and what admits
# one other than 1.5) and the mass reported with Tsuji's; the radii, materials, friction and wear change nothing
READ_JOINT_FIELDS = ("restitution", "restitution_speed_m_s", "impact_velocity_floor_m_s", "contact_damping",
                     "contact_exponent", "contact_model", "contact_stiffness_N_m1_5", "effective_mass_kg")


def check_joint_options(args) -> None:
    """A joint option given to contact-law, refused in one line unless a single impact's restitution reads it
    (:data:`READ_JOINT_FIELDS`): the others would leave its table and curves as they are."""
    for name, value in given_options(args, JointParameters).items():
        require(option_name(name), value, name in READ_JOINT_FIELDS,
                "only with a command that runs the joint: a single impact's restitution reads of the joint only "
                + ", ".join(map(option_name, READ_JOINT_FIELDS)))


def run(args) -> int:
    joint, mechanism = model_from_args(args, every_law=True)      # the table gives every law: each reads its own one
    check_joint_options(args)
    check_mechanism_options(args, mechanism)
    speeds = np.array(TABLE_SPEEDS_M_S)
    curves = restitution_curves(joint, speeds)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    np.savetxt(out / "contact_law.csv", np.column_stack([speeds, *(curves[law] for law in CONTACT_DAMPINGS)]),
               delimiter=",", header=",".join(["impact_speed_m_s", *map(column, CONTACT_DAMPINGS)]), comments="",
               fmt="%.10g")
    write_json_atomic(out / "contact_law.json", {
        "contact_damping": joint.contact_damping,
        "restitution": joint.restitution,
        "restitution_speed_m_s": joint.restitution_speed_m_s,
        "effective_mass_kg": joint.effective_mass_kg,
        "contact_exponent": joint.contact_exponent,
        # the joint's own law, then every law asked for the same restitution
        "curve": {"impact_speed_m_s": speeds, "restitution": curves[joint.contact_damping]},
        "laws": {law: curves[law] for law in CONTACT_DAMPINGS},
    })
    if not args.no_plots:
        plot_contact_law(joint, out / "contact_law.png")
    print(f"restitution of a single impact, asked {joint.restitution:g} (hunt-crossley: at "
          f"{joint.restitution_speed_m_s * 1e3:g} mm/s; tsuji: for {joint.effective_mass_kg:g} kg); * this joint's law")
    print(format_table(joint, speeds, curves))
    if joint.contact_model == "foundation":
        print(f"  note: {FOUNDATION_NOTE}")
    print(f"results in {out}")
    return 0


__all__ = ["add_arguments", "run", "restitution_curves", "plot_contact_law", "TABLE_SPEEDS_M_S", "PLOT_SPEEDS_M_S"]
