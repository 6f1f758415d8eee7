"""The errors of the ClearanceWearJoint FMU of both backends through fmpy: bad parameters, fixed values
and non-finite inputs fail with fmi2Error (a step fmi2Discard) naming the variable, logged with logging
off too, and the instance goes on (conftest.py's fixtures ``fmu`` and ``slave``)."""
import gc
import math

import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy_instance import FMI_DISCARD, FORCE_NAMES, P, Slave, contact_inputs  # noqa: E402

from wearjoint import ClearanceJoint  # noqa: E402


# ------------------------------------------------------------- errors
# The FMU's status shim turns the slave's errors into fmi2Error (pythonfmu alone: fmi2Fatal).
@pytest.mark.parametrize("name, value, allowed", [
    ("bushing_radius", 0.0099, "pin_radius"), ("restitution", 1.5, "[0.001, 1]"), ("friction_v1", 1e-4, "friction_v0"),
    ("rho_mode", 2, "paper"), ("contact_exponent", 2.0, "1.5 with contact_model"),   # the default foundation
])
def test_bad_parameter_fails_initialisation_with_fmi2_error_naming_it(fmu, name, value, allowed):
    kind = "integers" if isinstance(value, int) else "parameters"
    s = Slave(fmu, f"bad_{name}", **{kind: {name: value}})
    with pytest.raises(FMICallException) as failure:
        s.initialise()
    s.assert_failed_with_error(failure, name, repr(value), allowed)
    if fmu["backend"] == "pythonfmu":        # its message is the parameter set's (bushing_radius_m): both names
        s.assert_failed_with_error(failure, f"(the FMU's {name})")
    s.fmu.terminate()
    s.free()
    gc.collect()  # the host survives pythonfmu's reference release after the failure
    fresh = Slave(fmu, "after_failure").initialise()
    fresh.set_inputs(contact_inputs())
    assert fresh.get(["contact"])[0] == 1.0
    fresh.free()


def test_instance_is_reset_after_a_failed_initialisation(fmu):
    s = Slave(fmu, "reset", parameters={"restitution": 1.5})
    with pytest.raises(FMICallException):
        s.initialise()
    s.fmu.reset()
    gc.collect()
    s.start(parameters={"restitution": 0.8}).initialise()
    x = contact_inputs()
    s.set_inputs(x)
    expected = ClearanceJoint(P.replace(restitution=0.8)).evaluate(x[:6], x[6:])
    np.testing.assert_allclose(s.get(FORCE_NAMES[:3]), expected.pin_force, rtol=1e-12, atol=0)
    s.free()


def test_errors_are_logged_with_logging_off(fmu):
    s = Slave(fmu, "quiet", parameters={"restitution": 1.5}, logging_on=False)
    with pytest.raises(FMICallException) as failure:
        s.initialise()
    s.assert_failed_with_error(failure, "restitution")
    s.free()
    gc.collect()


def test_n_points_and_fixed_parameters_cannot_change(fmu, slave):
    s = Slave(fmu, "n_points")
    s.fmu.setInteger([s.vr["n_points"]], [P.n_points])  # the built value is accepted
    with pytest.raises(FMICallException) as failure:
        s.fmu.setInteger([s.vr["n_points"]], [100])
    s.assert_failed_with_error(failure, "n_points", "100")
    s.free()
    with pytest.raises(FMICallException) as failure:
        slave.fmu.setReal([slave.vr["restitution"]], [0.5])
    slave.assert_failed_with_error(failure, "restitution", "fixed")
    gc.collect()


def test_non_finite_input_fails_get_real_and_discards_do_step(slave, fmu):
    x = contact_inputs()
    x[0] = math.nan
    slave.set_inputs(x)
    with pytest.raises(FMICallException) as failure:
        slave.get(["normal_force", "worn_volume"])
    slave.assert_failed_with_error(failure, "normal_force", "pin_x=nan")
    assert slave.get(["worn_volume", "max_wear_depth"]).tolist() == [0.0, 0.0]  # not input-dependent
    with pytest.raises(FMICallException) as failure:
        slave.fmu.doStep(0.0, 1e-5)
    assert failure.value.status == FMI_DISCARD
    assert sum("dostep" in text.lower() and "pin_x" in text for text in slave.errors()) == 1
    slave.set_inputs(contact_inputs())
    slave.fmu.doStep(0.0, 1e-5)
    assert slave.get(["contact"])[0] == 1.0
    gc.collect()


def test_a_step_into_the_bushing_wall_is_discarded_and_a_shorter_one_continues(slave, fmu):
    """A co-simulation coupling that blew up hands the joint a pin deeper in the bushing wall than any contact
    (docs/reference/model.md §3.14): doStep returns fmi2Discard with one error line naming the time, the pin's overlap and
    the bound, the wear profile and the worn volume stay as they were, and the master's retry with the inputs of a
    shorter step goes on."""
    slave.set_inputs(contact_inputs())
    slave.fmu.doStep(0.0, 1e-5)
    names = [*fmu["wear"], "worn_volume", "max_wear_depth"]
    before = slave.get(names)
    slave.set_inputs(contact_inputs(depth=2.0 * P.admissible_penetration_m))
    with pytest.raises(FMICallException) as failure:
        slave.fmu.doStep(1e-5, 1e-5)
    assert failure.value.status == FMI_DISCARD
    refused = [text for text in slave.errors() if "into the" in text and "bushing wall" in text]
    assert len(refused) == 1 and "t=1e-05" in refused[0].replace("t=1.0000000000000001e-05", "t=1e-05")
    assert f"{P.admissible_penetration_m:g} m" in refused[0], refused
    # no '%' in the text: a host that formats the message it got as a format again (fmpy's container FMU passes it
    # on to its own host's logger so) read "2% of" as an octal conversion of an argument that is not there
    assert "%" not in refused[0], refused
    assert np.array_equal(slave.get(names), before)
    if fmu["backend"] == "native":      # a master without rollback asks whether to end there, and when it was
        from fmpy.fmi2 import fmi2LastSuccessfulTime, fmi2Terminated

        assert slave.fmu.getBooleanStatus(fmi2Terminated) and slave.fmu.getRealStatus(fmi2LastSuccessfulTime) == 1e-5
    slave.set_inputs(contact_inputs(depth=1e-6))
    slave.fmu.doStep(1e-5, 5e-6)
    if fmu["backend"] == "native":
        assert not slave.fmu.getBooleanStatus(fmi2Terminated)
    assert slave.get(["contact"])[0] == 1.0 and len(slave.errors()) == 1



def test_a_step_from_another_time_or_past_the_stop_time_is_an_error(fmu):
    """A master that lost or repeated a step (a communication point that is not the FMU's time) or steps past the
    stop time it set is told: fmi2Error with one line naming the times (FMI 2.0: fmi2DoStep past the stop time is an
    error; both were fmi2OK, the time then jumping to the master's), and the instance goes on from its own time."""
    s = Slave(fmu, "times", stop_time=3e-5)
    with pytest.raises(FMICallException) as failure:        # in initialisation mode (pythonfmu's was fmi2OK)
        s.fmu.doStep(0.0, 1e-5)
    s.assert_failed_with_error(failure, "oStep", "not allowed")
    s.initialise()
    s.set_inputs(contact_inputs())
    s.fmu.doStep(0.0, 1e-5)
    for t, h, words in ((7.0, 1e-5, ("currentCommunicationPoint=7 s is invalid", "1.0000000000000001e-05 s")),
                        (0.0, 1e-5, ("currentCommunicationPoint=0 s is invalid",)),
                        (1e-5, 1e-4, ("ends past the stop time 3.0000000000000001e-05 s",))):
        with pytest.raises(FMICallException) as failure:
            s.fmu.doStep(t, h)
        s.assert_failed_with_error(failure, "oStep", *words)
    s.fmu.doStep(1e-5, 1e-5)
    s.fmu.doStep(2e-5 + 1e-21, 1e-5)      # the master's time to rounding, to the stop time
    from fmpy.fmi2 import fmi2LastSuccessfulTime
    assert s.fmu.getRealStatus(fmi2LastSuccessfulTime) == pytest.approx(3e-5, rel=1e-12)
    assert len(s.errors()) == 4
    s.free()
