"""The joint FMU warns, once per instance, where the other engines refuse or a user has likely erred
(docs/reference/fmu.md §5): a wearing step over the wear-step limit (longer than 3e-5 s, or a share
lambda = k_f k_w F v dt of a conforming contact's penetration above 4, docs/reference/model.md §7), and a first step whose
inputs put the pin centre outside the bushing (offsets forgotten) or deeper in its wall than any contact.  Seen through fmpy's logger with
the status fmi2Warning / fmi3Warning; the step is accepted, the wear-step one with fmi2OK / fmi3OK."""
import math

import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy_instance import Joint  # noqa: E402

from wearjoint import paper_joint  # noqa: E402
from wearjoint.parameters import MAX_WEAR_STEP_S, WEAR_STEP_SHARE  # noqa: E402

WARNING, DISCARD = 1, 2
PENETRATION_M = 5e-6
INPUTS = ("pin_x", "pin_y", "pin_angle", "pin_vx", "pin_vy", "pin_omega",
          "bushing_x", "bushing_y", "bushing_angle", "bushing_vx", "bushing_vy", "bushing_omega")


def joint_parameters(wear_factor):
    return paper_joint(wear_factor=wear_factor).replace(pin_offset_m=(0.0, 0.0), bushing_offset_m=(0.0, 0.0))


def step_share(params, sliding_speed_m_s, step_s):
    """The share of the penetration one step wears, k_f k_w F v dt: a foundation pressure k_f delta at the
    deepest point, k_f = 3 K sqrt(c) / (4 sqrt(2) L sqrt(R_i R_j)) (docs/reference/model.md §3.10, §7)."""
    c = params.bushing_radius_m - params.pin_radius_m
    k_f = (3.0 * params.stiffness_N_m1_5 * math.sqrt(c)
           / (4.0 * math.sqrt(2.0) * params.contact_length_m * math.sqrt(params.pin_radius_m * params.bushing_radius_m)))
    return k_f * params.wear_coefficient_m2_N * params.wear_factor * sliding_speed_m_s * step_s


def sliding_in_contact(params, speed_m_s):
    """The pin pressed PENETRATION_M into the unworn bushing along x and turning in it, so that the
    bushing slides ``speed_m_s`` under it (the paper's sliding distance, (R_j + h) |omega_i - omega_j| dt,
    Eq. 33); the bushing body at rest at the origin, both centres at their bodies' reference points."""
    c = params.bushing_radius_m - params.pin_radius_m
    return (c + PENETRATION_M, 0.0, 0.0, 0.0, 0.0, speed_m_s / params.bushing_radius_m, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def started(fmus, version, params):
    return Joint(fmus[version], version, "cs", logging_on=True).start(params)


def warnings_of(joint):
    return [text for status, text in joint.log if status == WARNING]


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("wear_factor, speed, step_s, over", [
    (100.0, 0.1, 4e-6, False),     # share 0.14 at 4 us: inside the limit
    (100.0, 1.0, 4e-6, False),     # share 1.4: inside the relaxed update's limit (4)
    (100.0, 5.0, 4e-6, True),      # share 7: the step no longer resolves the wear
    (1.0, 1.0, 5e-5, True),        # share 0.18, but longer than 3e-5 s with wear
    (0.0, 4.0, 1e-3, False),       # no wear: any step
])
def test_a_wearing_step_over_the_limit_is_logged_once_and_the_step_ok(fmus, version, wear_factor, speed, step_s, over):
    params = joint_parameters(wear_factor)
    share = step_share(params, speed, step_s)
    assert over == (wear_factor > 0.0 and (share > WEAR_STEP_SHARE or step_s > MAX_WEAR_STEP_S))   # the cases are what they say
    joint = started(fmus, version, params)
    try:
        joint.set(INPUTS, sliding_in_contact(params, speed))
        assert joint.get(["normal_force"])[0] > 0.0
        statuses = [joint.do_step(k * step_s, step_s) for k in range(3)]
        assert joint.errors() == ""
        said = warnings_of(joint)
        if over:       # logged as a warning, returned OK: a master that stops on a warning status goes on
            assert statuses == [0, 0, 0] and len(said) == 1
            assert "wear-step limit" in said[0] and f"{step_s:g} s" in said[0] and "wear_factor" in said[0]
            assert joint.get(["max_wear_depth"])[0] > 0.0                  # the steps were taken
        else:
            assert statuses == [0, 0, 0] and said == []
    finally:
        joint.free()


@pytest.mark.parametrize("version", [2, 3])
def test_a_first_step_with_the_pin_outside_the_bushing_names_the_offsets(fmus, version):
    params = paper_joint(wear_factor=0.0)          # offsets set, as the slider-crank's
    joint = started(fmus, version, params)
    try:
        inputs = list(sliding_in_contact(params, 0.0))
        inputs[0] = 0.1                             # the crank pin's body reference 0.1 m from the rod's
        joint.set(INPUTS, inputs)
        assert joint.do_step(0.0, 1e-6) == WARNING
        (said,) = warnings_of(joint)
        assert "outside the bushing" in said and "pin_offset_x" in said and "bushing_offset_x" in said
        assert len(warnings_of(joint)) == 1
        # the first step only: a later one with the pin through the wall is refused (docs/reference/model.md §3.14)
        with pytest.raises(FMICallException) as refused:
            joint.do_step(1e-6, 1e-6)
        assert refused.value.status == DISCARD and "bushing wall" in joint.errors()
        assert len(warnings_of(joint)) == 1                                         # said once
    finally:
        joint.free()


@pytest.mark.parametrize("version", [2, 3])
def test_a_warning_status_is_logged_with_logging_off(fmus, version):
    """A call that returns a warning has called the logger (FMI 2.0 §2.1.3): fmusim ends its run at a warning, and
    with logging off (its default) the run had ended with an empty log.  A host that switches logStatusWarning off
    silences it; the wear-step warning, returned with OK, stays a logging-on message."""
    for silenced in (False, True):
        params = joint_parameters(100.0)
        joint = Joint(fmus[version], version, "cs", logging_on=False).start(params)
        try:
            if silenced:
                joint.fmu.setDebugLogging(False, ["logStatusWarning"])
            inputs = list(sliding_in_contact(params, 1.0))
            inputs[0] = 0.2                             # offsets forgotten: the pin 0.2 m from the bushing
            joint.set(INPUTS, inputs)
            assert joint.do_step(0.0, 1e-6) == WARNING
            said = warnings_of(joint)
            assert len(said) == (0 if silenced else 1) and all("are the offsets set" in text for text in said)
            joint.set(INPUTS, sliding_in_contact(params, 1.0))
            assert joint.do_step(1e-6, 5e-5) == 0 and len(joint.log) == len(said)    # over the wear-step limit
        finally:
            joint.free()


@pytest.mark.parametrize("version", [2, 3])
def test_a_first_step_with_the_pin_deep_in_the_wall_warns_and_wears_nothing(fmus, version):
    """0.4 mm into the wall, four clearances (a new user's inputs, 229 kN): the first step was taken with fmi2OK and
    no word, the second discarded.  Now the first says so (the step is still taken: a master may step once on start
    values) and wears nothing."""
    params = joint_parameters(1.0)
    joint = started(fmus, version, params)
    try:
        inputs = list(sliding_in_contact(params, 1.0))
        inputs[0] = params.bushing_radius_m - params.pin_radius_m + 4e-4
        joint.set(INPUTS, inputs)
        assert joint.do_step(0.0, 1e-6) == WARNING and joint.errors() == ""
        (said,) = warnings_of(joint)
        assert "the inputs put the pin 0.0004 m into the bushing wall (admissible" in said, said
        assert "first step is taken" in said and "wears nothing" in said
        assert joint.get(["max_wear_depth"])[0] == 0.0
        with pytest.raises(FMICallException) as refused:
            joint.do_step(1e-6, 1e-6)
        assert refused.value.status == DISCARD and "bushing wall" in joint.errors()
        assert len(warnings_of(joint)) == 1
    finally:
        joint.free()


@pytest.mark.parametrize("version", [2, 3])
def test_a_first_step_inside_the_bushing_says_nothing(fmus, version):
    params = joint_parameters(0.0)
    joint = started(fmus, version, params)
    try:
        joint.set(INPUTS, sliding_in_contact(params, 1.0))
        assert joint.do_step(0.0, 1e-6) == 0 and warnings_of(joint) == [] and joint.errors() == ""
    finally:
        joint.free()



@pytest.mark.parametrize("version", [2, 3])
def test_debug_logging_follows_the_model_descriptions_categories(fmus, version):
    """setDebugLogging's categories: a wear-step warning comes under logStatusWarning, not with logStatusError
    alone; a name not among the model description's LogCategories is an error naming it, nothing changed (both
    ignored the categories: the warning came through, a misspelt name was taken)."""
    from wearjoint.fmu.model_description import LOG_CATEGORIES

    assert [c.name for c in fmus[version]["md"].logCategories] == list(LOG_CATEGORIES)
    params = joint_parameters(1.0)

    def warned(*calls):
        """Wear-step warnings logged by a step over the limit (5e-5 s) after these setDebugLogging calls
        (loggingOn, categories) on an instance made with logging on; a call with a misspelt name is refused."""
        joint = started(fmus, version, params)
        try:
            for on, categories in calls:
                if "logStatusWarnings" in categories:
                    with pytest.raises(FMICallException) as refused:
                        joint.fmu.setDebugLogging(on, categories)
                    assert refused.value.status == 3
                    assert 'categories[0]="logStatusWarnings" is invalid: allowed logStatusError, logStatusWarning ' \
                           "or logAll" in joint.errors()
                else:
                    joint.fmu.setDebugLogging(on, categories)
            joint.set(INPUTS, sliding_in_contact(params, 1.0))
            assert joint.do_step(0.0, 5e-5) == 0
            return len(warnings_of(joint))
        finally:
            joint.free()

    off = (False, [])
    assert warned() == 1 and warned(off) == 0 and warned(off, (True, [])) == 1
    assert warned(off, (True, ["logStatusError"])) == 0 and warned(off, (True, ["logStatusWarning"])) == 1
    assert warned((False, ["logStatusWarning"])) == 0 and warned((False, ["logAll"])) == 1
    assert warned((False, ["logStatusWarnings"])) == 1            # refused: nothing changed
