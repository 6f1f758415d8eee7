"""exudyn's first solve in a process compiles the joint's kernels (numba's cache keeps them for later runs): a watch
of those compilations announces them once they last a few seconds (docs/reference/exudyn.md), closed when the first
solve accepts a step or ends without one, and none inside a command that watches its own."""
from __future__ import annotations

import pytest

exu = pytest.importorskip("exudyn")
from exudyn.itemInterface import NodeRigidBody2D, ObjectGround, ObjectRigidBody2D  # noqa: E402

from wearjoint import JointParameters, ParameterError  # noqa: E402
from wearjoint.exudyn import add_clearance_joint  # noqa: E402


def test_the_first_solve_watches_its_compilation_unless_a_command_does(monkeypatch):
    """The first force call of a process opens a watch of numba's compilations (its notice once they last 2 s: the
    first solve sat silent for up to a minute), closed at the first accepted step; inside a command that watches its
    own (validate: the compared engines' notice), none, so that nothing is announced twice."""
    from wearjoint._compile import notice

    monkeypatch.setattr(notice, "_first_use", [])
    notice.first_use_starts("exudyn")
    (stack, watch), = notice._first_use
    assert notice.watched() and watch.what == "exudyn"
    notice.first_use_over()
    assert notice._first_use == [None] and not notice.watched()
    monkeypatch.setattr(notice, "_first_use", [])
    with notice.watching("validate"):
        notice.first_use_starts("exudyn")
        assert notice._first_use == [None]


def test_a_first_solve_that_fails_before_a_step_closes_its_compilation_watch(monkeypatch):
    """A first solve refused before its first accepted step (a step too long for wear) leaves no watch open: the
    next solve's compilations are not announced as the first's."""
    import wearjoint.exudyn as wx
    from wearjoint._compile import notice

    monkeypatch.setattr(notice, "_first_use", [])
    mbs = exu.SystemContainer().AddSystem()          # a 1 kg bar hung from ground through a wearing joint
    bar = mbs.AddObject(ObjectRigidBody2D(nodeNumber=mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0, -0.1001, 0])),
                                          mass=1.0, inertia=1e-3))
    handle = add_clearance_joint(mbs, mbs.AddObject(ObjectGround()), bar,
                                 JointParameters(bushing_offset_m=(0.0, 0.1), wear_factor=1.0))
    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = 0.01
    settings.timeIntegration.verboseMode = 0
    settings.solution.file.write = False
    with pytest.raises(ParameterError, match="invalid with wear"):
        wx.solve_dynamic(mbs, settings)
    assert handle.accepted_steps == 0
    assert notice._first_use == [None] and not notice.watched()
