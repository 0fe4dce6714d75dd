"""python3 -m sinew batch ...: the same as `sinew batch ...`."""
import sys

from .batch import main

if len(sys.argv) > 1 and sys.argv[1] == "batch":
    sys.exit(main(sys.argv[2:]))
print("usage: python3 -m sinew batch INPUT... -o OUTDIR [options]   (see --help)", file=sys.stderr)
sys.exit(2)
