"""wearjoint.results.write_csv: the results folder's CSV files are what numpy.savetxt writes, byte for byte."""
import numpy as np
import pytest

from wearjoint.results import write_csv


@pytest.mark.parametrize("table", [
    np.array([[0.1, -2.5e-7, np.nan], [np.inf, 3.0, 1e300]]),       # NaN, infinities, tiny and huge values
    np.arange(5.0),                                                  # one column
    np.empty((0, 3)),                                                # no rows: the header alone
    np.array([[1, 2], [3, 4]]),                                      # integers, printed as floats
])
@pytest.mark.parametrize("fmt", ["%.10g", "%.17g"])
def test_write_csv_writes_what_savetxt_writes(tmp_path, table, fmt):
    names = [f"c{k}" for k in range(table.shape[1] if table.ndim == 2 else 1)]
    np.savetxt(tmp_path / "savetxt.csv", table, delimiter=",", header=",".join(names), comments="", fmt=fmt)
    write_csv(tmp_path / "ours.csv", table, names, fmt)
    assert (tmp_path / "ours.csv").read_bytes() == (tmp_path / "savetxt.csv").read_bytes()


def test_a_revolutions_values_read_back_exactly_at_17_digits(tmp_path):
    values = np.random.default_rng(3).normal(size=(100, 4)) * 10.0 ** np.arange(-6, 2, 2)
    write_csv(tmp_path / "t.csv", values, ["a", "b", "c", "d"], "%.17g")
    assert np.array_equal(np.loadtxt(tmp_path / "t.csv", delimiter=",", skiprows=1), values)
