"""What the whole-process timing scripts of bench/ share (fbx-load.py, peers.py): one timed run, and
their common arguments (--sinew, --runs, --testdata, --json)."""
import argparse
import os
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def run_ms(cmd, env):
    """Milliseconds the command took, whole process, and its exit status (output discarded)."""
    t = time.perf_counter()
    r = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return (time.perf_counter() - t) * 1000.0, r.returncode


def process_args(doc):
    """An argument parser described by the script's docstring, with the options every such script takes."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--sinew", default=os.path.join(HERE, "..", "build", "sinew"))
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--testdata", default=os.path.join(HERE, "..", "..", "shared", "testdata"))
    ap.add_argument("--json", action="store_true")
    return ap
