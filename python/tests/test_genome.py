"""Creatures as data: from_arrays of a model's arrays is the model; the vector
view round-trips bit for bit; bad arrays raise the engine's messages; the arrays
a model hands out are read-only (an edit raises, never is silently lost)."""
import numpy as np
import pytest

import sodaevo
from conftest import DAINTY, MODELS

ALL_MODELS = sorted(MODELS.glob("*.xml"))


def loaded(path):
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sodaevo.Model.load(path)


@pytest.mark.parametrize("path", ALL_MODELS, ids=lambda p: p.name)
def test_from_arrays_of_a_models_arrays_is_the_model(path):
    m = loaded(path)
    again = sodaevo.Model.from_arrays(**sodaevo.to_arrays(m))
    assert again == m and again.to_xml() == m.to_xml()


@pytest.mark.parametrize("path", ALL_MODELS, ids=lambda p: p.name)
def test_vector_round_trip_is_bit_exact(path):
    m = loaded(path)
    for world in (True, False):
        v = sodaevo.to_vector(m, world=world)
        assert sodaevo.from_vector(m, v, world=world) == m
        assert sodaevo.to_vector(sodaevo.from_vector(m, v, world=world), world=world).tobytes() == v.tobytes()
        low, high = sodaevo.vector_bounds(m, world=world)
        assert len(low) == len(high) == len(v) == len(sodaevo.vector_names(m, world=world))
        assert np.all(low <= v) and np.all(v <= high)


def test_vector_layout_is_the_documented_one():
    m = sodaevo.Model.load(DAINTY)
    links = m.links
    body = links[links["kind"] != 2]
    muscles = links[links["kind"] == 1]
    v = sodaevo.to_vector(m, world=False)
    expected = np.concatenate([body["rest_length"], muscles["amplitude"], muscles["phase"]])
    assert v.tobytes() == expected.tobytes()
    w = sodaevo.to_vector(m)
    world = m.world
    assert list(w[len(v):]) == [world[k] for k in ("gravity", "friction", "springyness", "surface_friction",
                                                    "surface_reflection", "wave_amplitude", "wave_speed")]
    names = sodaevo.vector_names(m)
    assert names[0].startswith("rest_length[") and names[-1] == "wave_speed"


def test_from_vector_changes_what_it_says_and_checks_bounds():
    m = sodaevo.Model.load(DAINTY)
    v = sodaevo.to_vector(m, world=False)
    n_muscles = int((m.links["kind"] == 1).sum())
    v2 = v.copy()
    v2[-1] = 1.25  # a phase wraps, as the file reader wraps it
    child = sodaevo.from_vector(m, v2, world=False)
    assert child.links[child.links["kind"] == 1]["phase"][-1] == 0.25
    v3 = v.copy()
    v3[len(v) - 2 * n_muscles] = 1.5  # an amplitude above 1
    with pytest.raises(sodaevo.InputError, match=r"vector\[\d+\] \(amplitude\[\d+\]\): expected a number in \[0.0, 1.0\]"):
        sodaevo.from_vector(m, v3, world=False)
    with pytest.raises(sodaevo.InputError, match="expected %d numbers" % len(v)):
        sodaevo.from_vector(m, v[:-1], world=False)


def test_bad_arrays_raise_the_engines_messages():
    m = sodaevo.Model.load(DAINTY)
    a = sodaevo.to_arrays(m)
    links = a["links"].copy()
    links["b"][0] = links["a"][0]
    with pytest.raises(sodaevo.InputError, match="model: link 0: expected two different nodes"):
        sodaevo.Model.from_arrays(a["nodes"], links, a["world"])
    links = a["links"].copy()
    links["a"][1] = 99
    with pytest.raises(sodaevo.InputError, match=r"links\[1\]: a, b: expected node indices"):
        sodaevo.Model.from_arrays(a["nodes"], links, a["world"])
    nodes = a["nodes"].copy()
    nodes[2, 0] = np.nan
    with pytest.raises(sodaevo.InputError, match="model: node 2 .*x: expected a finite number"):
        sodaevo.Model.from_arrays(nodes, a["links"], a["world"])
    with pytest.raises(sodaevo.InputError, match="model: environment: gravity: expected a value in"):
        sodaevo.Model.from_arrays(a["nodes"], a["links"], dict(a["world"], gravity=9.0))
    with pytest.raises(sodaevo.InputError, match="world: unknown key 'gravty'"):
        sodaevo.Model.from_arrays(a["nodes"], a["links"], {"gravty": 1.0})
    with pytest.raises(sodaevo.InputError, match=r"nodes: expected an \(n, 4\) array"):
        sodaevo.Model.from_arrays(a["nodes"][:, :3], a["links"])


def test_a_plain_table_builds_a_creature_that_runs():
    nodes = [[100, 100, 0, 0], [150, 100, 0, 0], [125, 60, 0, 0]]
    links = [[0, 0, 1, 50, 0, 0], [1, 1, 2, 47, 0.5, 0.25], [0, 2, 0, 47, 0, 0]]
    m = sodaevo.Model.from_arrays(nodes, links, name="triangle")
    assert (m.mass_count, m.link_count, m.node_ids) == (3, 3, ("m0", "m1", "m2"))
    assert sodaevo.Model.from_xml(m.to_xml()).to_xml() == m.to_xml()  # the file's canonical order
    assert sodaevo.simulate(m, 200)["frames"] == 200


def test_arrays_are_read_only():
    m = sodaevo.Model.load(DAINTY)
    for array in (m.nodes, m.masses, m.fixed, m.links):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = array[1]
    with pytest.raises(TypeError):
        m.world["gravity"] = 0.0
    edited = m.nodes.copy()  # the way to change one: a copy, then from_arrays
    edited[0, 0] += 1
    moved = sodaevo.Model.from_arrays(edited, m.links, dict(m.world), fixed=m.fixed, node_ids=m.node_ids, name=m.name,
                                      comment=m.comment)
    assert moved.nodes[0, 0] == m.nodes[0, 0] + 1 and moved != m
