"""race() against `sodaevo race --json`: the same results, places and replicas."""
import sodaevo
from conftest import MODELS, cli_json

FLAT = MODELS / "terrains" / "TerrainFlat.xml"
CONTENDERS = [MODELS / "dainty_walker.xml", MODELS / "wodka_m1.xml", MODELS / "carefulslug.xml"]


def test_race_is_the_command_lines():
    cli = cli_json("race", FLAT, *CONTENDERS, "--timeout", 2500, "--json")
    py = sodaevo.race(str(FLAT), [str(c) for c in CONTENDERS], timeout=2500)
    assert py == cli


def test_race_replicas_are_the_command_lines():
    cli = cli_json("race", FLAT, CONTENDERS[1], "--timeout", 1500, "--replicas", 4, "--json")
    py = sodaevo.race(str(FLAT), [str(CONTENDERS[1])], timeout=1500, replicas=4, threads=2)
    assert py == cli


def test_a_model_races_as_its_file():
    by_file = sodaevo.race(FLAT, [CONTENDERS[1]], timeout=1500)["contenders"][0]
    by_model = sodaevo.race(FLAT, [sodaevo.Model.load(CONTENDERS[1])], timeout=1500)["contenders"][0]
    assert by_model["frames"] == by_file["frames"] and by_model["finished"] == by_file["finished"]
