"""``ClearanceJoint``'s API at its edges: a bad argument is one ParameterError line naming it, its value and what is
allowed; a step over the wear-step limit warns once (as the FMU, docs/reference/model.md §7); a pin too deep in
the wall is named as such (§3.14); ``restart`` begins a new trajectory on the worn bushing."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from wearjoint import ClearanceJoint, JointParameters
from wearjoint.core import layout as L
from wearjoint.parameters import ParameterError

PIN = [0.0, 0.0, 0.0, 0.0, 0.0, 10.0]                   # turning at 10 rad/s
BUSHING = [0.0, 1e-4 + 1e-6, 0.0, 0.0, 0.0, 0.0]        # the pin 1 um into the unworn bushing (clearance 0.1 mm)
KINEMATICS = r"allowed 6 finite numbers \(x \[m\], y \[m\], angle \[rad\], vx \[m/s\], vy \[m/s\], omega \[rad/s\]\)"


def _one_line(exc_info) -> str:
    text = str(exc_info.value)
    assert "\n" not in text
    return text


@pytest.mark.parametrize("call, message", [
    (lambda j: j.evaluate(["a"] * 6, BUSHING),
     r"^parameter pin_kinematics=\['a', 'a', 'a', 'a', 'a', 'a'\] is invalid \(not real numbers\): " + KINEMATICS),
    (lambda j: j.evaluate({"x": 0}, BUSHING), r"^parameter pin_kinematics=\{'x': 0\} is invalid \(not real numbers\)"),
    (lambda j: j.evaluate(PIN, [0j] * 6), r"^parameter bushing_kinematics=\[0j, 0j, 0j, 0j, 0j, 0j\] is invalid"),
    (lambda j: j.evaluate(PIN, [[0.0], [1.0, 2.0]]), r"^parameter bushing_kinematics=\[\[0.0\], \[1.0, 2.0\]\] is inv"),
    (lambda j: j.evaluate(PIN, [0.0] * 5), r"^parameter bushing_kinematics=\[0.0, 0.0, 0.0, 0.0, 0.0\] is invalid "
                                           r"\(not 6 numbers: shape \(5,\)\): " + KINEMATICS),
    (lambda j: j.advance(PIN, BUSHING, "1e-5"), r"^parameter dt='1e-5' is invalid: allowed a finite step >= 0 s$"),
    (lambda j: j.advance(PIN, BUSHING, None), r"^parameter dt=None is invalid: allowed a finite step >= 0 s$"),
    (lambda j: j.advance(PIN, BUSHING, [1e-5]), r"^parameter dt=\[1e-05\] is invalid: allowed a finite step >= 0 s$"),
    (lambda j: j.advance(PIN, BUSHING, True), r"^parameter dt=True is invalid: allowed a finite step >= 0 s$"),
    (lambda j: j.advance(PIN, BUSHING, 1e-5, held="yes"), r"^parameter held='yes' is invalid: allowed True or False$"),
    (lambda j: j.state_from_bytes(None), r"^parameter data=None is invalid: allowed the bytes of a state"),
    (lambda j: j.state_from_bytes("abc"), r"^parameter data='abc' is invalid: allowed the bytes of a state"),
    (lambda j: j.set_state(b"abc"), r"^parameter state=b'abc' is invalid: allowed a JointState"),
    (lambda j: j.set_wear_profile(np.array(["a"] * 1257)),
     r"^parameter wear_depth_m=\['a', 'a', 'a', 'a', 'a', 'a', \.\.\.\] "),
    (lambda j: j.set_wear_profile(["a"] * 1257),
     r"^parameter wear_depth_m=\['a', 'a', 'a', 'a', 'a', 'a', \.\.\.\] is invalid \(not real numbers\): "
     r"allowed n_points=1257 depths \[m\] in \[0, 0.0101\]$"),
    (lambda j: j.set_wear_profile(np.zeros((1257, 1))),
     r"^wear profile: an array of shape \(1257, 1\) given, this joint has n_points=1257: allowed shape \(1257,\)$"),
    (lambda j: j.replay_wear(np.zeros((1, 7)), "a"), r"^scale='a' is invalid: allowed a finite value >= 0$"),
])
def test_a_bad_argument_is_one_line_naming_it_its_value_and_what_is_allowed(call, message):
    joint = ClearanceJoint(JointParameters(wear_factor=100))
    joint.advance(PIN, BUSHING, 1e-5)
    before = joint.state_to_bytes()
    with pytest.raises(ParameterError) as exc_info:
        call(joint)
    assert _one_line(exc_info) and exc_info.match(message)
    assert joint.state_to_bytes() == before                  # nothing changed


@pytest.mark.parametrize("params", ["x", {}, {"restitution": 0.5}, 0])
def test_a_joint_of_anything_but_a_parameter_set_is_refused(params):
    """Not the defaults in silence for an empty dict or 0, nor an AttributeError for a string."""
    with pytest.raises(ParameterError, match=r"^params=.* is invalid: allowed a wearjoint.JointParameters \(or None"):
        ClearanceJoint(params)
    assert ClearanceJoint(None).params == JointParameters()


def test_a_step_wearing_through_the_wall_names_the_wear_rate_it_comes_from():
    """A wear factor fast enough that one microsecond wears more than the bushing radius: the refusal names
    k_w * wear_factor, not the step alone."""
    joint = ClearanceJoint(JointParameters(wear_coefficient_m2_N=1e-6, wear_factor=1e6))     # both at their bounds
    with pytest.raises(ParameterError, match=r"^parameter dt=1e-06 is invalid here: the step would wear the bushing by "
                                             r"more than its radius .* at k_w \* wear_factor = .* \* 1000000.0 "
                                             r"m\^2/N; allowed a shorter step or a smaller wear_coefficient_m2_N or "
                                             r"wear_factor; the joint is unchanged$") as exc_info:
        joint.advance(PIN, BUSHING, 1e-6)
    assert _one_line(exc_info) and joint.max_wear_depth_m == 0.0


def test_numpy_numbers_and_integers_are_real_numbers():
    joint = ClearanceJoint(JointParameters(wear_factor=100))
    joint.advance(np.array(PIN), np.array(BUSHING), np.float64(1e-5), held=np.bool_(True))
    joint.advance([0] * 6, [0, 0, 0, 0, 0, 0], 0)
    joint.set_wear_profile(np.zeros(1257, dtype=int))


def test_a_step_over_the_wear_step_limit_warns_once_per_joint_naming_dt_and_the_limit():
    """The kernel flags a wearing step over 3e-5 s (STEP_OVERSHOT): advance accepts it and warns once, as the FMU
    does; steps within the limit do not warn; another joint warns again."""
    joint = ClearanceJoint(JointParameters(wear_factor=100))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        joint.advance(PIN, BUSHING, 1e-5)                    # within the limit: silent
    with pytest.warns(RuntimeWarning, match=r"a wearing step dt=0\.01 s is over the wear-step limit \(longer than 3e-05 s"):
        joint.advance(PIN, BUSHING, 0.01)
    assert joint.max_wear_depth_m > 0.0                      # accepted
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        joint.advance(PIN, BUSHING, 0.01)                    # said once per joint
    with pytest.warns(RuntimeWarning, match=r"dt=0\.001 s is over the wear-step limit"):
        ClearanceJoint(JointParameters(wear_factor=100)).advance(PIN, BUSHING, 1e-3)
    # within 3e-5 s the share of the penetration a step wears is what passed: said so (it named both limits)
    with pytest.warns(RuntimeWarning, match=r"dt=2e-05 s is over the wear-step limit \(within 3e-05 s, but the share "
                                            r"k_f k_w F v dt of the contact's penetration it wears passed 4\)"):
        ClearanceJoint(JointParameters(wear_factor=1e4)).advance(PIN, BUSHING, 2e-5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ClearanceJoint(JointParameters(wear_factor=0.0)).advance(PIN, BUSHING, 0.01)   # no wear: no limit


def test_a_pin_too_deep_in_the_wall_is_named_and_the_joint_unchanged():
    """After an accepted point, kinematics that put the pin 4.9 mm into the wall (0.2 mm admissible) are refused
    saying so, not blaming dt."""
    joint = ClearanceJoint(JointParameters(wear_factor=100))
    joint.advance(PIN, BUSHING, 1e-5)
    before = joint.state_to_bytes()
    with pytest.raises(ParameterError) as exc_info:
        joint.advance(PIN, [-0.005, 0.0, 0.0, 0.0, 0.0, 0.0], 1e-5)
    text = _one_line(exc_info)
    assert text.startswith("parameters pin_kinematics=[0, 0, 0, 0, 0, 10] and bushing_kinematics=[-0.005, 0, 0, 0, 0, "
                           "0] are invalid here: they put the pin deeper into the bushing wall or press it harder than "
                           "any contact of this joint, 0.0049 m with a normal force of ")
    assert "allowed at most 0.0002 m (0.02 times the pin radius)" in text and "dt" not in text
    assert joint.state_to_bytes() == before


def test_restart_applies_the_pending_wear_and_forgets_the_contact_memory():
    """A new trajectory on the worn bushing: the wear batch still pending (two steps of 1e-5 s, short of the 3e-5 s
    batch) is applied, not lost, and the contact memory is a new joint's."""
    joint = ClearanceJoint(JointParameters())
    for _ in range(2):
        joint.advance([*PIN[:5], 1.0], BUSHING, 1e-5)
    assert joint.memory[L.M_BATCH_TIME] == pytest.approx(2e-5) and joint.memory[L.M_ACTIVE] == 1.0
    assert joint.worn_volume_m3 == 0.0
    joint.restart()
    assert joint.worn_volume_m3 > 0.0                     # the batch applied, not lost
    assert np.array_equal(joint.memory, ClearanceJoint(JointParameters()).memory)
    profile = joint.wear_profile[1]
    joint.restart()                                          # nothing pending: nothing changes
    assert np.array_equal(joint.wear_profile[1], profile)
