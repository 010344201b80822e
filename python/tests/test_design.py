"""`rfeid.design` against `rfeid design -o`."""
import json
from pathlib import Path

import pytest

import rfeid
from conftest import EXAMPLES, seconds_to_stop


def test_design_equals_the_command_lines_document(tmp_path, rfeid_cli, knee_column):
    out = tmp_path / "design.json"
    rfeid_cli("design", knee_column, "--choose", "3", "-o", out, "-q")
    cli = json.loads(out.read_text())
    d = rfeid.design(rfeid.Model.load(knee_column), choose=3)
    assert d.document == cli
    assert len(d.chosen) == 3 and d.efficiency_at_least <= 1.0
    for name, se in d.std_errors.items():
        assert se <= d.placed_std_errors[name] * (1 + 1e-12)
    assert d.report(tmp_path / "r").endswith("report.html")
    assert "chosen" in repr(d)


def test_a_design_before_the_first_test_reads_the_file_itself(tmp_path, rfeid_cli, knee_column):
    # Every sensor a candidate: Model.load refuses the file (there is
    # nothing to measure), rfeid.design(path) chooses all three, as the
    # command line does.
    text = Path(knee_column).read_text()
    unplaced = text.replace("(2 % of its RMS): for `rfeid design`", "\ncandidate = true")
    assert unplaced.count("candidate = true") == 24
    path = tmp_path / "unplaced.toml"
    path.write_text(unplaced)
    with pytest.raises(rfeid.ModelError, match="every \\[\\[sensor\\]\\] is a candidate"):
        rfeid.Model.load(path)
    d = rfeid.design(path, choose=3)
    out = tmp_path / "design.json"
    rfeid_cli("design", path, "--choose", "3", "-o", out, "-q")
    assert d.document == json.loads(out.read_text())
    assert len(d.chosen) == 3 and d.document["compared_with"] == "no_sensor"
    with pytest.raises(TypeError, match="rfeid.Model or a path"):
        rfeid.design(3, choose=3)


def test_design_requests_are_checked(knee_column):
    m = rfeid.Model.load(knee_column)
    with pytest.raises(ValueError, match="choose at least one"):
        rfeid.design(m, choose=0)
    with pytest.raises(ValueError, match="over_box without choose"):
        rfeid.design(m, over_box=4)
    lathe = rfeid.Model.load(EXAMPLES / "lathe" / "model.toml")
    with pytest.raises(rfeid.ModelError, match="no candidate sensors"):
        rfeid.design(lathe, choose=2)
    with pytest.raises(rfeid.ModelError, match="outside its box"):
        rfeid.design(m, set={"a_n1": 1e20})


def test_ctrl_c_stops_a_box_design_within_a_second(knee_column):
    m = rfeid.Model.load(knee_column)
    took = seconds_to_stop(lambda: rfeid.design(m, choose=2, over_box=4096))
    print(f"stopped {took:.3f} s after SIGINT")
    assert took < 1.0
