"""wearjoint.fmu.extracted: an FMU's files extracted once per FMU file and shared by its instances; a changed file
gets its own folder; where the cache cannot be written each instance extracts into a folder it owns and removes."""
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from wearjoint.cosim.master_layout import OUTPUT_NAMES
from wearjoint.fmu import extracted
from wearjoint.fmu.instance import N_INPUTS, FmuInstance
from wearjoint.parameters import paper_joint


def _instance(fmu):
    return FmuInstance(fmu, paper_joint(wear_factor=0.0), np.zeros(N_INPUTS), np.zeros(len(OUTPUT_NAMES)),
                       OUTPUT_NAMES)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setattr(extracted, "extraction_root", lambda: tmp_path / "extracted")
    return tmp_path / "extracted"


def test_instances_share_one_extraction_that_outlives_them(native_fmu, cache):
    first, second = _instance(native_fmu), _instance(native_fmu)
    try:
        assert first.unzip_dir == second.unzip_dir and Path(first.unzip_dir).parent == cache
        first.exchange(0.0)
        second.exchange(0.0)
    finally:
        first.close()
    assert (Path(second.unzip_dir) / "modelDescription.xml").is_file()   # closing one left the other's files
    second.close()
    assert len(list(cache.iterdir())) == 1


def test_a_changed_fmu_file_gets_its_own_folder_and_old_ones_are_pruned(native_fmu, cache, tmp_path):
    copy = tmp_path / "copy.fmu"
    shutil.copy(native_fmu, copy)
    folders = []
    for k in range(extracted.KEEP + 2):
        os.utime(copy, ns=(10**18 + k, 10**18 + k))     # the same bytes, another modification time
        folder, description, owned = extracted.extracted_fmu(copy)
        assert not owned and description.modelName == "ClearanceWearJoint"
        folders.append(folder)
    assert len(set(folders)) == extracted.KEEP + 2
    kept = {p.name for p in cache.iterdir()}
    assert len(kept) == extracted.KEEP and Path(folders[-1]).name in kept


def test_an_unwritable_cache_leaves_each_instance_its_own_folder(native_fmu, tmp_path, monkeypatch):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    monkeypatch.setattr(extracted, "extraction_root", lambda: blocker / "extracted")
    instance = _instance(native_fmu)
    folder = Path(instance.unzip_dir)
    assert folder.is_dir() and not folder.is_relative_to(blocker)
    instance.close()
    assert not folder.exists()
