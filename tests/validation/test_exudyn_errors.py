"""``wearjoint.exudyn`` at its edges (docs/reference/exudyn.md §8): a bad argument is one ParameterError line naming
it, its value and what is allowed, before any solve; a second solve of the same system is a new run that loses
nothing (the README's 1 kg bar hung from ground)."""
from __future__ import annotations

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")
from exudyn.itemInterface import (  # noqa: E402
    LoadMassProportional, MarkerBodyMass, NodeRigidBody2D, ObjectGround, ObjectRigidBody2D,
)

from wearjoint import JointParameters  # noqa: E402
from wearjoint.exudyn import (  # noqa: E402
    UNACCEPTED_FORCE_TIMES, add_clearance_joint, check_step, set_post_step, simulation_settings, solve_dynamic,
)
from wearjoint.parameters import ParameterError  # noqa: E402

WEARING = JointParameters(bushing_offset_m=(0.0, 0.1), wear_factor=100)


def hung_bar(joint=True):
    """The README's system: (mbs, bar, ground, handle or None), not assembled."""
    mbs = exu.SystemContainer().AddSystem()
    bar = mbs.AddObject(ObjectRigidBody2D(nodeNumber=mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0, -0.1001, 0])),
                                          mass=1.0, inertia=1e-3))
    mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=bar)),
                                     loadVector=[0, -9.81, 0]))
    ground = mbs.AddObject(ObjectGround())
    return mbs, bar, ground, add_clearance_joint(mbs, ground, bar, WEARING) if joint else None


def refused(message: str, call) -> None:
    """``call()`` raises one ParameterError line matching ``message`` (a regex)."""
    with pytest.raises(ParameterError) as exc_info:
        call()
    assert "\n" not in str(exc_info.value)
    exc_info.match(message)


def test_the_same_body_as_an_int_and_as_exudyns_index_is_refused():
    """exudyn's ObjectIndex never equals an int: the bar as both is refused whichever way it is numbered."""
    mbs, bar, _, _ = hung_bar(joint=False)
    for pin in (bar, int(bar)):
        refused(rf"^bushing_body={int(bar)} is invalid: it is pin_body too \(allowed: another body\)$",
                lambda: add_clearance_joint(mbs, pin, int(bar), JointParameters()))


@pytest.mark.parametrize("arguments, message", [
    ((0.05, 0), r"^parameter step_s=0 is invalid: allowed a finite step > 0 s$"),
    ((0.05, float("nan")), r"^parameter step_s=nan is invalid: allowed a finite step > 0 s$"),
    ((0.05, -1e-5), r"^parameter step_s=-1e-05 is invalid: allowed a finite step > 0 s$"),
    ((0.05, "1e-5"), r"^parameter step_s='1e-5' is invalid: allowed a finite step > 0 s$"),
    ((float("inf"), 1e-5), r"^parameter end_time_s=inf is invalid: allowed a finite time > 0 s$"),
    ((-1, 1e-5), r"^parameter end_time_s=-1 is invalid: allowed a finite time > 0 s$"),
    ((1e300, 1e-300), r"^parameter step_s=1e-300 is invalid: allowed at least end_time_s / 2\*\*53 = 1.1\d*e\+284 s$"),
    ((0.05, 1e-5, "abc"), r"^parameter handles='abc' is invalid: allowed a sequence of the handles add_clearance"),
    ((0.05, 1e-5, [1]), r"^parameter handles=\[1\] is invalid: allowed a sequence of the handles add_clearance_joint"),
    ((0.05, 1e-5, (), "1"), r"^parameter coordinate_scale_m='1' is invalid: allowed a finite length > 0 m$"),
])
def test_simulation_settings_refuses_bad_arguments_up_front(arguments, message):
    refused(message, lambda: simulation_settings(*arguments))


def test_a_step_too_long_for_a_wearing_joint_is_refused_by_the_settings_and_check_step():
    *_, handle = hung_bar()
    message = r"^parameter step_s=0.001 is invalid with wear: allowed at most 3e-05 s \(set wear_factor=0"
    refused(message, lambda: simulation_settings(0.05, 1e-3, [handle]))
    refused(message, lambda: check_step(1e-3, [handle]))
    refused(r"^parameter step_s='1e-3' is invalid: allowed a finite step > 0 s$", lambda: check_step("1e-3", [handle]))
    refused(r"^parameter handles=<wearjoint.ex.* is invalid: allowed a sequence", lambda: check_step(1e-5, handle))
    assert simulation_settings(0.05, 1e-3).timeIntegration.numberOfSteps == 50       # no wearing joint: allowed


def test_set_post_step_refuses_what_is_not_a_function_and_keeps_the_one_set():
    mbs, *_ = hung_bar()
    user_function = lambda mbs, t: True  # noqa: E731
    set_post_step(mbs, user_function)
    refused(r"^parameter user_function='x' is invalid: allowed a function f\(mbs, t\) -> bool, or None$",
            lambda: set_post_step(mbs, "x"))
    assert mbs.GetPostStepUserFunction()["function"].user_function is user_function


def test_a_post_step_function_set_over_the_joints_stops_the_solve_naming_the_fix():
    """``mbs.SetPostStepUserFunction`` after the joint replaced the joints' post-step function: the solve ran to its
    end with no step accepted, no wear and an empty history.  It now stops within UNACCEPTED_FORCE_TIMES steps,
    naming set_post_step; the same function given to set_post_step runs after the joint, which wears."""
    mbs, _, _, handle = hung_bar()
    seen = []
    mbs.SetPostStepUserFunction(lambda mbs_, t: seen.append(t) or True)
    mbs.Assemble()
    message = (r"post-step user function <function .* is invalid with clearance joints: set by "
               r"mbs.SetPostStepUserFunction after add_clearance_joint.*allowed: wearjoint.exudyn.set_post_step\(mbs, f\)")
    with pytest.raises(ParameterError, match=message):        # the joint's own error, not exudyn's wrap of its text
        solve_dynamic(mbs, simulation_settings(0.005, 1e-5, [handle]))
    assert handle.accepted_steps == 0 and 0 < len(seen) <= UNACCEPTED_FORCE_TIMES + 2

    mbs, _, _, handle = hung_bar()
    seen = []
    set_post_step(mbs, lambda mbs_, t: seen.append(t) or True)
    mbs.Assemble()
    solve_dynamic(mbs, simulation_settings(0.005, 1e-5, [handle]))
    assert handle.accepted_steps == 500 and len(seen) == 501 and handle.joint.worn_volume_m3 > 0.0


def test_a_second_solve_is_a_new_run_on_the_worn_bushing_losing_nothing():
    """exudyn starts each solve at its start time from the initial state: the second solve of 5 ms is a new run whose
    every step wears (as much as a new joint's 5 ms run, on a bushing that already wore in the first 2 ms), and the
    history keeps each run apart, the first unchanged."""
    mbs, _, _, handle = hung_bar()
    mbs.Assemble()
    solve_dynamic(mbs, simulation_settings(0.002, 1e-5, [handle]))
    first, first_volume = handle.history(), handle.joint.worn_volume_m3
    solve_dynamic(mbs, simulation_settings(0.005, 1e-5, [handle]))
    fresh_mbs, _, _, fresh = hung_bar()
    fresh_mbs.Assemble()
    solve_dynamic(fresh_mbs, simulation_settings(0.005, 1e-5, [fresh]))

    assert handle.runs == 2 and handle.accepted_steps == 700
    assert all(np.array_equal(handle.history(0)[name], first[name]) for name in first)
    second = handle.history()
    assert second["time_s"].size == 500 and np.allclose(second["time_s"], fresh.history()["time_s"])   # no step skipped
    assert (handle.joint.worn_volume_m3 - first_volume) == pytest.approx(fresh.joint.worn_volume_m3, rel=0.01)
    assert second["max_wear_depth_m"][0] >= first["max_wear_depth_m"][-1] > 0.0       # the worn profile kept
    refused(r"^parameter run=2 is invalid: allowed an integer in \[-2, 1\] \(this handle has 2 run\(s\)\)$",
            lambda: handle.history(2))


def test_a_solve_continuing_at_the_last_end_time_continues_the_run():
    """exudyn's continuation (startTime = the last end time): the same run, its history one time series."""
    mbs, _, _, handle = hung_bar()
    mbs.Assemble()
    solve_dynamic(mbs, simulation_settings(0.001, 1e-5, [handle]))
    settings = simulation_settings(0.001, 1e-5, [handle])
    settings.timeIntegration.startTime, settings.timeIntegration.endTime = 0.001, 0.002
    solve_dynamic(mbs, settings)
    times = handle.history()["time_s"]
    assert handle.runs == 1 and times.size == 200 and np.all(np.diff(times) > 0.0)
    # 600 steps of 1e-5 s end at 0.005999999999999924, a continuation starts at 0.006: the same time, no 8e-17 s step
    mbs, _, _, handle = hung_bar()
    mbs.Assemble()
    solve_dynamic(mbs, simulation_settings(0.006, 1e-5, [handle]))
    assert handle.t != 0.006 and handle.t == pytest.approx(0.006, abs=1e-15)
    settings = simulation_settings(0.001, 1e-5, [handle])
    settings.timeIntegration.startTime, settings.timeIntegration.endTime = 0.006, 0.007
    solve_dynamic(mbs, settings)
    times = handle.history()["time_s"]
    assert handle.runs == 1 and handle.accepted_steps == times.size == 700 and np.all(np.diff(times) > 5e-6)


def test_a_first_solve_may_start_at_any_time_and_a_later_start_is_a_new_run():
    """A new system solved from startTime 0.5 s accepts its 100 steps of 1e-5 s from there (its initial state is no
    0.5 s step: with wear that was refused as a step too long); a second solve starting after the last step's end
    (not a continuation) is a new run, as one starting before it."""
    mbs, _, _, handle = hung_bar()
    mbs.Assemble()
    settings = simulation_settings(0.001, 1e-5, [handle])
    settings.timeIntegration.startTime, settings.timeIntegration.endTime = 0.5, 0.501
    solve_dynamic(mbs, settings)
    times = handle.history()["time_s"]
    assert handle.runs == 1 and times.size == 100 and times[0] == pytest.approx(0.50001)
    assert times[-1] == pytest.approx(0.501, abs=1e-12)
    settings.timeIntegration.startTime, settings.timeIntegration.endTime = 0.7, 0.701
    solve_dynamic(mbs, settings)
    assert handle.runs == 2 and handle.history(0)["time_s"].size == 100
    assert handle.history()["time_s"].size == 100 and handle.history()["time_s"][0] == pytest.approx(0.70001)


def test_a_run_that_starts_deep_in_the_wall_is_told_to_check_its_start_not_its_step():
    """A start that puts the pin 1 mm into a 0.1 mm clearance's wall is refused when the joint is added; moved there
    for a second solve (the node's coordinates set anew, read at the solve's start), it is refused as that solve
    starts, with the same words and no step taken (it had stopped the run at its second step with "a normal force
    of 0 N"); no advice to shorten a step."""
    mbs = exu.SystemContainer().AddSystem()
    node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0, -0.101, 0]))
    bar = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=1.0, inertia=1e-3))
    ground = mbs.AddObject(ObjectGround())
    with pytest.raises(ParameterError, match=r"0.001 m from the bushing centre at the initial configuration, deeper in "
                                             r"its wall than any contact reaches"):
        add_clearance_joint(mbs, ground, bar, WEARING)
    mbs.SetNodeParameter(node, "referenceCoordinates", [0, -0.1, 0])
    handle = add_clearance_joint(mbs, ground, bar, WEARING)
    mbs.Assemble()
    solve_dynamic(mbs, simulation_settings(0.001, 1e-5, [handle]))      # within the clearance: it runs
    steps = handle.accepted_steps
    mbs.SetNodeParameter(node, "referenceCoordinates", [0, -0.101, 0])   # a second solve from 0, 1 mm deep
    mbs.Assemble()
    with pytest.raises(ParameterError, match=r"0.001 m from the bushing centre at the initial configuration this "
                                             r"solve starts from, deeper in its wall") as failure:
        solve_dynamic(mbs, simulation_settings(0.001, 1e-5, [handle]))
    assert "shorter step" not in str(failure.value) and handle.accepted_steps == steps


def test_a_joints_error_inside_the_solve_is_raised_as_it_is():
    """A step too long for wear, found by the joint inside exudyn's solve: exudyn wraps the user function's error in
    its own (ModelError, the message inside its text with exudyn's frames), which ``except ParameterError`` missed;
    solve_dynamic raises the joint's ParameterError, one line."""
    mbs, _, _, handle = hung_bar()
    mbs.Assemble()
    settings = simulation_settings(0.001, 1e-5, [handle])
    settings.timeIntegration.numberOfSteps = 10                    # 1e-4 s steps, over the wear-step limit
    refused(r"^the solver's step 0.0001 s \(t = 0.0001 s\) is invalid with wear: allowed at most 3e-05 s",
            lambda: solve_dynamic(mbs, settings))


def test_a_joint_at_a_place_that_has_one_and_a_body_at_nan_are_refused():
    """Two joints between the same bodies at the same offsets (one bushing) each carried half the load, without a
    word, and so did one 1 nm off; a body whose initial coordinates are not finite was blamed on the joint's offsets
    ("nan m from the bushing centre")."""
    mbs, bar, ground, _ = hung_bar()
    for offset in ((0.0, 0.1), (1e-9, 0.1), (0.0, 0.1 + 0.9e-4)):          # within the clearance, 1e-4 m
        same = JointParameters(bushing_offset_m=offset, wear_factor=100)
        refused(r"^parameter bushing_body=.* is invalid: allowed a place no other joint has: joint 0 of this system "
                r"joins these bodies within the clearance \(0.0001 m\) of these offsets",
                lambda: add_clearance_joint(mbs, ground, bar, same))
    refused(r"joint 0 of this system joins these bodies within the clearance", lambda: add_clearance_joint(
        mbs, bar, ground, JointParameters(pin_offset_m=(0.0, 0.1), bushing_offset_m=(0.0, 0.0))))   # roles swapped
    other = JointParameters(bushing_offset_m=(0.05, 0.1), pin_offset_m=(0.05, 0.0), wear_factor=100)
    add_clearance_joint(mbs, ground, bar, other)                   # a second bearing 5 cm along: taken
    mbs = exu.SystemContainer().AddSystem()
    bar = mbs.AddObject(ObjectRigidBody2D(nodeNumber=mbs.AddNode(NodeRigidBody2D(
        referenceCoordinates=[float("nan"), -0.1001, 0])), mass=1.0, inertia=1e-3))
    refused(r"^parameter bushing_body=.* is invalid: allowed a body whose coordinates \(x, y, angle\) are finite at "
            r"the initial configuration \(they are \(nan, -0.1001, 0.0\)\)",
            lambda: add_clearance_joint(mbs, mbs.AddObject(ObjectGround()), bar, WEARING))



def test_a_joint_restored_into_a_new_system_goes_on_as_the_continuation():
    """A swinging bar: its joint's state saved at 2 ms and restored into a new system started from the same
    coordinates goes on bit for bit as exudyn's continuation of the first.  The force at the new solve's start
    (exudyn's initial accelerations) was counted as inside its first step, which then wore with the explicit
    solvers' mean force instead of the step's end force (9.8e-12 m apart in a new user's pendulum)."""
    def swinging():
        mbs = exu.SystemContainer().AddSystem()
        node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0, -0.1001, 0], initialVelocities=[0.2, 0, 2.0]))
        bar = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=1.0, inertia=1e-3))
        mbs.AddLoad(LoadMassProportional(markerNumber=mbs.AddMarker(MarkerBodyMass(bodyNumber=bar)),
                                         loadVector=[0, -9.81, 0]))
        handle = add_clearance_joint(mbs, mbs.AddObject(ObjectGround()), bar, WEARING)
        mbs.Assemble()
        return mbs, handle

    def from_to(mbs, handle, start, end):
        settings = simulation_settings(end - start, 1e-5, [handle])
        settings.timeIntegration.startTime, settings.timeIntegration.endTime = start, end
        solve_dynamic(mbs, settings)

    def final_into_initial(mbs, q, v):
        mbs.systemData.SetODE2Coordinates(q, configuration=exu.ConfigurationType.Initial)
        mbs.systemData.SetODE2Coordinates_t(v, configuration=exu.ConfigurationType.Initial)

    first, kept = swinging()
    from_to(first, kept, 0.0, 0.002)
    saved = kept.joint.state_to_bytes()
    q, v = first.systemData.GetODE2Coordinates(), first.systemData.GetODE2Coordinates_t()
    final_into_initial(first, q, v)
    from_to(first, kept, 0.002, 0.004)
    second, restored = swinging()
    final_into_initial(second, q, v)
    restored.joint.state_from_bytes(saved)
    from_to(second, restored, 0.002, 0.004)
    went_on = kept.history()
    assert kept.runs == 1 and went_on["max_wear_depth_m"][-1] > went_on["max_wear_depth_m"][-201] > 0.0   # wearing
    assert np.array_equal(restored.history()["time_s"], went_on["time_s"][-200:])
    assert np.array_equal(restored.joint.wear_depth, kept.joint.wear_depth)
    assert np.array_equal(restored.history()["normal_force_N"], went_on["normal_force_N"][-200:])
