"""Ctrl-C stops simulate, evaluate and race within a second (SIGINT sent by the
test to a child Python) with KeyboardInterrupt, and importing the module loads no
MPI library."""
import os
import subprocess
import sys
import textwrap

import pytest

import sodaevo
from conftest import DAINTY, MODELS

PACKAGE_PARENT = os.path.dirname(os.path.dirname(os.path.abspath(sodaevo.__file__)))

CHILD = textwrap.dedent("""
    import os, signal, sys, threading, time
    import sodaevo
    m = sodaevo.Model.load({dainty!r})
    calls = {{
        "simulate": lambda: sodaevo.simulate(m, 10**9),
        "simulate_trace": lambda: sodaevo.simulate(m, 10**7, trace=True),
        "evaluate": lambda: sodaevo.evaluate([m] * 4, {{"frames": 10**7}}, threads=2),
        "race": lambda: sodaevo.race({race!r}, [m] * 2, timeout=49997, replicas=64, threads=2),
    }}
    call = calls[sys.argv[1]]
    threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    sent = time.monotonic() + 0.5
    try:
        call()
        print("finished")
    except KeyboardInterrupt:
        print("interrupted %.3f" % (time.monotonic() - sent))
""")


@pytest.mark.parametrize("call", ["simulate", "simulate_trace", "evaluate", "race"])
def test_ctrl_c_stops_within_a_second(call):
    script = CHILD.format(dainty=str(DAINTY), race=str(MODELS / "terrains" / "TerrainFlat.xml"))
    env = dict(os.environ, PYTHONPATH=PACKAGE_PARENT)
    out = subprocess.run([sys.executable, "-c", script, call], capture_output=True, text=True, env=env,
                         timeout=60).stdout.split()
    assert out[0] == "interrupted", out
    assert float(out[1]) < 1.0


def test_import_loads_no_mpi():
    script = "import sodaevo; print(open('/proc/self/maps').read())"
    env = dict(os.environ, PYTHONPATH=PACKAGE_PARENT)
    maps = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, check=True).stdout
    assert "_sodaevo" in maps and "libmpi" not in maps
