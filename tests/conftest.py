"""Shared pytest fixtures."""
import pytest


@pytest.fixture(scope="session")
def built_fmu(tmp_path_factory):
    """ClearanceWearJoint.fmu (default n_points) built once per session into a temporary folder."""
    from wearjoint.fmu.build_pythonfmu import build_fmu

    return build_fmu(tmp_path_factory.mktemp("fmu"))
