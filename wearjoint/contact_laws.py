"""The contact damping laws as a model-form error bar (docs/reference/model.md §3.5): each law, and each law's free
parameter at the ends of its plausible range, as changes to a joint.

``validate`` and ``sensitivity`` run a case under each variant and report how far the answers move: the spread a
user should set beside the sampling (chaotic) spread, since no law is singled out by the paper's dynamics.
"""
from __future__ import annotations

from .parameters import SliderCrankParameters


def contact_law_variants(mechanism: SliderCrankParameters) -> tuple[tuple[str, dict], ...]:
    """(label, joint changes) of every law and of each free parameter's plausible range: Hunt-Crossley's v_r from
    12.5 to 200 mm/s (the paper case's onset speeds, 25 % to 99 %), the Lankarani-Nikravesh laws' velocity floor at
    1 and 10 mm/s, Tsuji's effective mass from the one the clearance joint decelerates across the rod
    (:attr:`SliderCrankParameters.rod_across_mass_kg`) to the one along it
    (:attr:`SliderCrankParameters.contact_effective_mass_kg`)."""
    across = mechanism.rod_across_mass_kg
    along = mechanism.contact_effective_mass_kg
    return (("hunt-crossley v_r 50 mm/s", {"contact_damping": "hunt-crossley", "restitution_speed_m_s": 0.05}),
            ("hunt-crossley v_r 12.5 mm/s", {"contact_damping": "hunt-crossley", "restitution_speed_m_s": 0.0125}),
            ("hunt-crossley v_r 200 mm/s", {"contact_damping": "hunt-crossley", "restitution_speed_m_s": 0.2}),
            ("lankarani-nikravesh (paper)", {"contact_damping": "lankarani-nikravesh"}),
            ("lankarani-nikravesh-exact", {"contact_damping": "lankarani-nikravesh-exact"}),
            ("lankarani-nikravesh-exact floor 10 mm/s", {"contact_damping": "lankarani-nikravesh-exact",
                                                         "impact_velocity_floor_m_s": 0.01}),
            (f"tsuji m_eff {along:.3g} kg", {"contact_damping": "tsuji", "effective_mass_kg": along}),
            (f"tsuji m_eff {across:.3g} kg", {"contact_damping": "tsuji", "effective_mass_kg": across}))
