"""Every column of a study's ``unbalance`` analysis read off the swept speeds says so (issue 29
section 7; helper report31).

A study's ``amplification_factor`` and ``required_margin_pct`` carried the netCDF attribute
``peak_search`` (swept speeds, not the exact search of ``unbalance`` and ``report``); the peak's own
speed and amplitude, its separation margin and the force rows' peaks come from the same swept
search and did not say so (3f1536e: no ``peak_search`` on them). Checked on the file written and read
back; each peak speed is one of the swept speeds (``speeds_rpm`` expanded here with numpy).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import rotordyn_modal as rdm

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SWEPT = ("unbalance_peak_amplitude", "unbalance_peak_speed", "amplification_factor", "separation_margin_pct",
         "required_margin_pct", "force_peak_amplitude", "force_peak_speed")
STUDY = """
seed = 1
samples = 2
design = "latin-hypercube"

[[parameters]]
key = "suspensions.mount-FL.stiffness"
apply = "scale"
distribution = "uniform"
low = 0.9
high = 1.1

[analyses.unbalance]
speeds_rpm = "300:3000:12"
operating_speed_rpm = 1500.0
forces = "suspensions"
"""


def _written(tmp_path):
    """The study of gear_machine run by the command line into ``s.nc``, read back with xarray."""
    import xarray as xr

    from rotordyn_modal.cli.main import main

    spec = tmp_path / "s.study.toml"
    spec.write_text(STUDY)
    out = tmp_path / "s.nc"
    assert main(["study", str(EXAMPLES / "gear_machine.toml"), "--spec", str(spec), "--out", str(out),
                 "--table", str(tmp_path / "s.csv")]) == 0
    with xr.open_dataset(out) as data:
        return data.load()


def test_every_swept_column_says_so_in_the_file(tmp_path, capsys):
    import pandas as pd

    data = _written(tmp_path)
    err = capsys.readouterr().err
    for name in SWEPT:
        assert name in data, name
        assert data[name].attrs.get("peak_search", "").startswith("swept speeds"), name
    assert data["force_peak_speed"].attrs["units"] == "rad/s"
    swept = rdm.rpm(np.linspace(300.0, 3000.0, 12))
    for name in ("unbalance_peak_speed", "force_peak_speed"):
        speeds = data[name].values
        speeds = speeds[np.isfinite(speeds)]
        assert speeds.size
        assert np.all(np.min(np.abs(speeds[:, None] - swept[None, :]), axis=1) <= 1e-12 * swept.max()), name
    said = [line for line in err.splitlines() if "read off the swept speeds" in line]
    assert len(said) == 1 and all(name in said[0] for name in SWEPT)
    columns = pd.read_csv(tmp_path / "s.csv").columns       # the names scripts read, unchanged
    for name in SWEPT:
        assert any(c.startswith(name + "[") for c in columns), name
