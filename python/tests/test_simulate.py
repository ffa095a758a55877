"""simulate() against `sodaevo simulate`: the same bits, summary and trace."""
import csv

import numpy as np
import pytest

import sodaevo
from conftest import DAINTY, MODELS, cli_json, run_cli

FRAMES = 600


def read_trace_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], np.array([[float(v) for v in r] for r in rows[1:]])
    masses = (len(header) - 3) // 4
    return body[:, 1], body[:, 3:].reshape(len(body), masses, 4)


@pytest.mark.parametrize("model, args", [
    ("dainty_walker.xml", {}),
    ("wheel.xml", {}),
    ("dainty_walker.xml", {"mode": "continuous", "integrator": "rk4", "substeps": 4}),
])
def test_summary_is_the_command_lines(model, args):
    cli = cli_json("simulate", MODELS / model, "--frames", FRAMES, "--json",
                   *sum((["--" + k, str(v)] for k, v in args.items()), []))
    py = sodaevo.simulate(sodaevo.Model.load(MODELS / model), FRAMES, **args)
    for key in ("frames", "masses", "links", "centroid_dx", "centroid_dy", "px_per_frame", "stepping",
                "fixed_bars", "bar_engine", "diverged"):
        assert py[key] == cli[key], key


def test_trace_is_the_command_lines(tmp_path):
    run_cli("simulate", DAINTY, "--frames", FRAMES, "--trace", tmp_path / "t.csv")
    phases, cli_trace = read_trace_csv(tmp_path / "t.csv")
    py = sodaevo.simulate(sodaevo.Model.load(DAINTY), FRAMES, trace=True)
    assert py["trace"].shape == (FRAMES + 1, sodaevo.Model.load(DAINTY).mass_count, 4)
    assert py["trace"].dtype == np.float64
    assert np.array_equal(py["trace"], cli_trace)  # exact: the CSV holds shortest round-trip doubles
    assert np.array_equal(py["wave_phase"], phases)
    # The trace's last frame is where the summary says the run ended.
    assert py["trace"][0, :, 0].mean() + py["centroid_dx"] == pytest.approx(py["trace"][-1, :, 0].mean())


def test_replicas_are_the_command_lines():
    cli = cli_json("simulate", DAINTY, "--frames", 300, "--replicas", 4, "--settle", 50, "--json")
    py = sodaevo.simulate(sodaevo.Model.load(DAINTY), 300, replicas=4, settle=50)
    assert list(py["distances"]) == cli["distances"]
    for key in ("n", "mean", "median", "sd", "min", "max", "horizon", "non_finite"):
        assert py[key] == cli[key], key
    assert list(py["interval95"]) == cli["interval95"]


def test_model_arrays_and_xml_round_trip():
    m = sodaevo.Model.load(DAINTY)
    assert m.nodes.shape == (len(m.node_ids), 4) and m.masses.shape == (m.mass_count, 4)
    assert m.links.dtype.names == ("kind", "a", "b", "rest_length", "amplitude", "phase")
    assert len(m.links) == m.link_count and m.world["gravity"] == 0.38046992
    again = sodaevo.Model.from_xml(m.to_xml())
    assert again.to_xml() == m.to_xml()
    import copy, pickle
    assert pickle.loads(pickle.dumps(m)) == m and copy.deepcopy(m) == m
