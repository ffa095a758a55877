"""Bad input raises sodaevo.InputError with where it is; never a crash."""
import pytest

import sodaevo
from conftest import DAINTY, MODELS


def test_missing_model_file(tmp_path):
    with pytest.raises(sodaevo.InputError) as e:
        sodaevo.Model.load(tmp_path / "none.xml")
    assert "none.xml" in str(e.value)


def test_bad_xml_names_line_and_column():
    text = "<model>\n<nodes>\n<mass id=\"m0\" x=\"abc\" y=\"1\"/>\n</nodes>\n</model>\n"
    with pytest.raises(sodaevo.InputError) as e:
        sodaevo.Model.from_xml(text, "bad.xml")
    assert (e.value.file, e.value.line) == ("bad.xml", 3) and e.value.column > 1
    assert isinstance(e.value, ValueError)


def test_bad_config_names_the_json_pointer(tmp_path):
    m = sodaevo.Model.load(DAINTY)
    with pytest.raises(sodaevo.InputError) as e:
        sodaevo.evaluate([m], {"frames": 0})
    assert e.value.pointer == "/fitness/frames" and e.value.file == "<dict>"
    with pytest.raises(sodaevo.InputError) as e:
        sodaevo.evaluate([m], {"frames": 100, "framez": 1})
    assert e.value.pointer == "/fitness/framez"
    bad = tmp_path / "bad.json"
    bad.write_text('{"fitness": {"frames": 100,}}')
    with pytest.raises(sodaevo.InputError) as e:
        sodaevo.evaluate([m], bad)
    assert e.value.file == str(bad) and e.value.line == 1


def test_bad_arguments():
    m = sodaevo.Model.load(DAINTY)
    with pytest.raises(sodaevo.InputError, match="mode"):
        sodaevo.simulate(m, 10, mode="quantum")
    with pytest.raises(sodaevo.InputError, match="integrator"):
        sodaevo.simulate(m, 10, integrator="rk4")  # needs mode="continuous"
    with pytest.raises(sodaevo.InputError, match="replicas"):
        sodaevo.evaluate([m], replicas=0)
    with pytest.raises(TypeError):
        sodaevo.evaluate(["not a model"])
    with pytest.raises(sodaevo.InputError):
        sodaevo.race(MODELS / "terrains" / "TerrainFlat.xml", [DAINTY], timeout=0)
    with pytest.raises(sodaevo.InputError):
        sodaevo.race(DAINTY, [DAINTY])  # a model is no race file
