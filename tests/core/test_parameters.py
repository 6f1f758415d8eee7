"""Parameter defaults, the stiffness helper (Eqs. 16-17) and validation messages."""
import math

import pytest

from wearjoint import JointParameters, ParameterError, SliderCrankParameters, contact_stiffness
from wearjoint.parameters import effective_modulus


def test_stiffness_internal_form_reproduces_table_2():
    k = JointParameters().stiffness_from_materials("internal")
    assert k == pytest.approx(7.95e10, rel=5e-4)


def test_the_default_stiffness_follows_the_radii_and_materials():
    """Without a given K the joint uses Eqs. 16-17 of its own radii and materials (K ~ E* sqrt(R)); a
    given K overrides them; a K the materials cannot give (exponent != 1.5) must be given."""
    paper = JointParameters()
    assert paper.contact_stiffness_N_m1_5 is None
    assert paper.stiffness_N_m1_5 == paper.stiffness_from_materials()
    # the bushing 10x softer: E* = 1/((1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j), K = 4 E* sqrt(R)/3 by hand
    soft = paper.replace(bushing_youngs_modulus_Pa=7.17e9)
    e_star = 1.0 / ((1 - 0.29 ** 2) / 207e9 + (1 - 0.33 ** 2) / 7.17e9)
    assert soft.stiffness_N_m1_5 == pytest.approx(4 / 3 * e_star * math.sqrt(0.01 * 0.0101 / 0.0001), rel=1e-12)
    assert soft.stiffness_N_m1_5 < 0.15 * paper.stiffness_N_m1_5
    looser = paper.replace(bushing_radius_m=0.0104)        # 4x the clearance: R = R_i R_j / c about 4x smaller
    assert looser.stiffness_N_m1_5 / paper.stiffness_N_m1_5 == pytest.approx(math.sqrt(0.0104 / 0.0101 / 4), rel=1e-12)
    given = paper.replace(contact_stiffness_N_m1_5=1e10, bushing_youngs_modulus_Pa=7.17e9)
    assert given.stiffness_N_m1_5 == 1e10
    assert given.foundation_modulus_N_m3 == pytest.approx(paper.foundation_modulus_N_m3 * 1e10 / paper.stiffness_N_m1_5)
    with pytest.raises(ParameterError, match=r"contact_exponent=2.0 is invalid: allowed > 0, and 1.5 with "
                                             r"contact_model='foundation' .*, and 1.5 with no contact_stiffness_N_m1_5 "
                                             r"given \(K from the materials\)"):
        JointParameters(contact_exponent=2.0)
    # the deepest point's law: only the condition that holds is stated
    with pytest.raises(ParameterError, match=r"^parameter contact_exponent=2.0 is invalid: allowed > 0, and 1.5 with "
                                             r"no contact_stiffness_N_m1_5 given \(K from the materials\)$"):
        JointParameters(contact_model="deepest", contact_exponent=2.0)
    assert JointParameters(contact_model="deepest", contact_exponent=2.0, contact_stiffness_N_m1_5=1e12).stiffness_N_m1_5 == 1e12


def test_stiffness_external_form_is_the_printed_sum_form():
    k = JointParameters().stiffness_from_materials("external")
    assert k == pytest.approx(5.6e9, rel=1e-2)


def test_stiffness_by_hand():
    # Eq. 16 by hand for equal materials: H = (1 - nu^2)/(pi E), K = 4/(3 pi 2H) sqrt(R_i R_j/(R_j - R_i))
    e, nu, ri, rj = 200e9, 0.3, 0.01, 0.0102
    h = (1 - nu * nu) / (math.pi * e)
    expected = 4 / (3 * math.pi * 2 * h) * math.sqrt(ri * rj / (rj - ri))
    assert contact_stiffness(ri, rj, e, nu, e, nu) == pytest.approx(expected, rel=1e-14)


def test_effective_modulus_standard_hertz():
    # equal materials: E* = E / (2 (1 - nu^2))
    assert effective_modulus(100e9, 0.25, 100e9, 0.25) == pytest.approx(100e9 / (2 * (1 - 0.0625)), rel=1e-14)


def test_defaults_are_the_paper_tables():
    j = JointParameters()
    m = SliderCrankParameters()
    assert j.clearance_m == pytest.approx(1e-4)
    assert (j.n_points, j.restitution, j.friction_coefficient) == (1257, 0.9, 0.1)
    assert m.omega_rad_s == pytest.approx(150 * 2 * math.pi / 60)
    assert (m.crank_length_m, m.rod_length_m, m.slider_mass_kg) == (0.05, 0.22, 0.7)


BAD_JOINT = [
    ("bushing_radius_m", 0.0099, "pin_radius_m"),
    ("bushing_radius_m", 0.0100, "pin_radius_m"),
    ("n_points", 7, "from 8 to 1000000"),
    ("n_points", 1_000_001, "from 8 to 1000000"),
    ("n_points", 100.5, "integer"),
    ("pin_youngs_modulus_Pa", 0.0, "> 0"),
    ("bushing_youngs_modulus_Pa", -1.0, "> 0"),
    ("pin_poisson_ratio", 0.5, "(0, 0.5)"),
    ("bushing_poisson_ratio", 0.0, "(0, 0.5)"),
    ("restitution", 0.0, "[0.001, 1]"),
    ("restitution", 1.2, "[0.001, 1]"),
    ("friction_coefficient", -0.1, "in [0, 10]"),
    ("friction_v1_m_s", 1e-3, "friction_v0_m_s"),
    ("wear_coefficient_m2_N", -1e-10, ">= 0"),
    ("wear_factor", -2.0, ">= 0"),
    ("pin_radius_m", float("nan"), "finite"),
    ("contact_stiffness_N_m1_5", float("inf"), "finite"),
    ("contact_length_m", 0.0, "> 0"),
    ("rho_mode", "flat", "conformal"),
    ("wear_placement", "everywhere", "patch"),
    ("sliding_distance", "guess", "rotation"),
    ("pin_offset_m", (0.0, float("nan")), "finite"),
]


@pytest.mark.parametrize("name,value,allowed", BAD_JOINT)
def test_bad_joint_parameter_is_named_in_the_error(name, value, allowed):
    with pytest.raises(ParameterError) as err:
        JointParameters(**{name: value})
    text = str(err.value)
    assert name in text and repr(value)[:6] in text and allowed in text


def test_a_radius_past_the_other_names_both_values():
    """A pin radius set past the default bushing's: the error names the bushing radius the rule checks and the pin
    radius the user set, with both values."""
    with pytest.raises(ParameterError) as err:
        JointParameters(pin_radius_m=0.02)
    text = str(err.value)
    assert "bushing_radius_m=0.0101" in text and "> pin_radius_m (pin_radius_m = 0.02)" in text and "\n" not in text


BAD_MECHANISM = [
    ("crank_mass_kg", 0.0), ("rod_mass_kg", -1.0), ("slider_mass_kg", float("nan")),
    ("crank_length_m", 0.0), ("rod_length_m", 0.04), ("crank_inertia_kg_m2", -1e-3),
    ("crank_speed_rpm", 0.0), ("gravity_m_s2", float("inf")),
]


@pytest.mark.parametrize("name,value", BAD_MECHANISM)
def test_bad_mechanism_parameter_is_named_in_the_error(name, value):
    with pytest.raises(ParameterError, match=name):
        SliderCrankParameters(**{name: value})


@pytest.mark.parametrize("field, value", [("pin_radius_m", "abc"), ("restitution", [1]), ("contact_damping", 3),
                                          ("wear_factor", None)])
def test_a_value_of_the_wrong_type_is_named_in_one_line(field, value):
    """Not a number where the table's rule wants one (or not a name where it wants a choice): the one-line error
    naming the field and the rule, not Python's conversion error."""
    with pytest.raises(ParameterError, match=rf"^parameter {field}=.* is invalid: allowed "):
        JointParameters(**{field: value})


def test_a_wear_factor_too_fast_for_any_step_is_refused_by_name_with_its_bound():
    """The default largest step with wear is the wear-step limit, inversely proportional to k_w x the wear factor
    (docs/reference/model.md §7): a factor whose limit falls below min_step_s is refused naming wear_factor (not the
    min_step_s a user never set) and the largest factor allowed, which runs."""
    import re

    from wearjoint.parameters import paper_joint
    from wearjoint.simulation_options import SimulationOptions

    options, k_w = SimulationOptions(), 1e-6              # the largest k_w a joint takes: 1980 times the printed
    with pytest.raises(ParameterError, match=r"^parameter wear_factor=100000.0 is invalid: .* below min_step_s"
                                             r" = 1e-10 s: allowed at most ") as failure:
        options.for_joint(paper_joint(wear_coefficient_m2_N=k_w, wear_factor=1e5))
    bound = float(re.search(r"allowed at most (\S+) ", str(failure.value)).group(1))
    assert 5.05e3 < bound < 5.05e4            # 1e7 to 1e8 at the printed k_w
    assert options.for_joint(paper_joint(wear_coefficient_m2_N=k_w, wear_factor=0.999 * bound)).max_step_s >= 1e-10
    with pytest.raises(ParameterError, match="^parameter wear_factor="):
        options.for_joint(paper_joint(wear_coefficient_m2_N=k_w, wear_factor=1.001 * bound))


def test_a_wear_coefficient_too_fast_for_any_step_is_refused_by_its_own_name_with_its_bound():
    """The same limit reached by k_w at the default wear factor 1 (a crank at 1e5 rpm, min_step_s 1e-7 s) is named
    wear_coefficient_m2_N, not the wear_factor=1.0 the user never set."""
    import re

    from wearjoint.parameters import SliderCrankParameters, paper_joint
    from wearjoint.simulation_options import SimulationOptions

    options, fast = SimulationOptions(min_step_s=1e-7), SliderCrankParameters(crank_speed_rpm=1e5)
    with pytest.raises(ParameterError, match=r"^parameter wear_coefficient_m2_N=1e-06 is invalid: .* below min_step_s"
                                             r" = 1e-07 s: allowed at most \S+ with this wear factor") as failure:
        options.for_joint(paper_joint(fast, wear_coefficient_m2_N=1e-6), fast)
    bound = float(re.search(r"allowed at most (\S+) ", str(failure.value)).group(1))
    assert options.for_joint(paper_joint(fast, wear_coefficient_m2_N=0.999 * bound), fast).max_step_s >= 1e-7
    with pytest.raises(ParameterError, match="^parameter wear_coefficient_m2_N="):
        options.for_joint(paper_joint(fast, wear_coefficient_m2_N=1.001 * bound), fast)


@pytest.mark.parametrize("changes, named", [
    ({}, None),                                                            # the paper's 10 mm pin
    ({"pin_radius_m": 0.1, "bushing_radius_m": 0.1001}, None),             # an eccentric sheave: past the crank only
    ({"pin_radius_m": 10.0, "bushing_radius_m": 10.1}, "pin_radius_m=10"),  # 10 mm written where metres are asked
    ({"contact_length_m": 12.0}, "contact_length_m=12"),
])
def test_a_joint_longer_than_the_crank_and_rod_both_gets_a_note_naming_the_length(changes, named):
    from wearjoint.parameters import joint_size_note

    note = joint_size_note(JointParameters(**changes), SliderCrankParameters())["joint_size_note"]
    if named is None:
        assert note is None
    else:
        assert note.startswith(f"{named} is longer than the mechanism's crank and rod (0.05 m, 0.22 m)")
        assert note.endswith("lengths are in metres")
