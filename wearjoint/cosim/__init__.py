"""Co-simulation master: the rigid slider-crank coupled to the ``ClearanceWearJoint`` FMU.

The crank-rod joint of the mechanism is open (``MODE_EXTERNAL``); its loads come
from the FMU (docs/reference/fmu.md §5).  fmpy loads, instantiates and initialises the
FMU (``FMU2Slave``); the communication loop (:func:`master_loop`) is numba code
that calls the FMU's ``fmi2DoStep``/``fmi2SetReal``/``fmi2GetReal`` (and the
FMU-state functions for rollbacks) through their C entry points, with value
references and values in pre-allocated arrays, so the master adds no Python
work per step.  Each communication step [t, t + h]: the FMU already holds the
kinematics at t (crank = pin body, rod = bushing body) and its forces were read;
:func:`communication_step` records the point t and integrates the mechanism over
the step with those forces held (RK4); then ``doStep(t, h)``, ``setReal`` of the
12 inputs at t + h and ``getReal`` of the 12 outputs the master needs.

Schemes (``CoSimulationOptions.scheme``):

* ``zoh`` -- fixed communication step ``step_s``, forces held (zero-order hold).
* ``extrapolation`` -- fixed step; while the contact persists (in contact at t
  and at the point before) the forces are extrapolated linearly from the last
  two points and their mean over the step is held (second order in h).
* ``adaptive`` -- extrapolation, ``step_s`` while the pin touches the bushing; in free flight
  the step grows up to ``max_step_s``, limited by the predicted time to the next
  contact onset (from the FMU's signed penetration and its rate).  A step that
  starts in free flight and ends deeper than ``onset_penetration_m`` is rolled
  back (``getFMUstate``/``setFMUstate`` plus the mechanism state) and retried
  with a step interpolated to the onset, as ``core.integrators.integrate`` does
  for DOPRI.  Free flight carries no joint force, so large steps there cost no
  accuracy.  In contact the step is halved (down to ``step_s``/16) while the force
  at a step's end misses its extrapolation by > 30 %, and grows back otherwise:
  the explicit coupling is unstable at a fixed step in deep or hard-damped contact; 5 us in contact by
  default.  Zero-order hold is first order in h (pointwise 100x off the monolithic run at 1 us) and
  unstable from ~5 us on (stiff contact).
* ``linearised`` -- ``adaptive``, but in contact the loads are linearised instead of extrapolated: at each
  accepted point in contact the master reads the joint's Jacobian in its 12 inputs from the FMU (its published
  ``d_*_d_*`` outputs in one ``fmi2GetReal``, the same kernels' exact derivatives) and integrates
  F0 + J (u - u0) through the RK4 stages of the next step (``core.linearisation``; no loads where the
  linear normal force reaches 0: the contact ended).  The default: its contact step chosen by the miss of
  that prediction (``coupling_tolerance`` 0.003, the step the miss is expected to meet, second order in h),
  at most ``step_s`` = 10 us and at least an eighth of it, each contact starting at a quarter (the
  linearisation at an onset knows nothing of the stiffening ahead).  Within 2 standard errors of the
  monolithic RK4 ensembles on the paper's mechanism unworn and worn, the own mechanism with wear and a
  5.7-clearance groove, and closer to the monolithic path over the first impacts than ``adaptive`` at 5 us
  (docs/explanation/cosim_study.md, "Ensembles on worn grooves").
"""
from ..fmu.ensure import ensure_fmu
from ..fmu.instance import INPUT_NAMES
from .cosimulation import CoSimulation, CoSimulationError, CoSimulationOptions, run_cosimulation
from .master_layout import OUTPUT_NAMES, SCHEMES

__all__ = ["CoSimulation", "CoSimulationOptions", "CoSimulationError", "run_cosimulation", "ensure_fmu",
           "communication_step", "INPUT_NAMES", "OUTPUT_NAMES", "SCHEMES"]


def __getattr__(name):
    """``communication_step``, numba's kernel, imported when asked for (a co-simulation runs the compiled library's
    and imports no numba)."""
    if name == "communication_step":
        from .master_loop import communication_step

        return communication_step
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
