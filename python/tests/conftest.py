"""Where the tests find libsinew, the sinew program and the shared test models.

CTest sets $SINEW_LIBRARY, $SINEW_CLI and $SINEW_TESTDATA; run by hand from the source tree,
the build/ folder and ../shared/testdata are used."""
import os
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))


def _testdata():
    return os.environ.get("SINEW_TESTDATA") or os.path.join(ROOT, "..", "shared", "testdata")


@pytest.fixture(scope="session")
def testdata():
    path = _testdata()
    if not os.path.isdir(path):
        pytest.skip("shared test data not found (%s); set SINEW_TESTDATA to ../shared/testdata" % path)
    return path


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("SINEW_CLI") or os.path.join(ROOT, "build", "sinew")
    if not os.access(path, os.X_OK):
        pytest.skip("the sinew program is not built (%s)" % path)
    return path
