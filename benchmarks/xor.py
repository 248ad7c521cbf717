"""XOR benchmark of MENTOR against NEAT's reference (100/100 solved, 4,755 evaluations).

Usage: ``python benchmarks/xor.py [--runs 100] [--seed 0] [--workers 2]``; the logic lives in
:mod:`mentor_core.cli.xor` (also installed as ``mentor-xor``). Prints one JSON object.
"""

from __future__ import annotations

import sys

from mentor_core.cli.xor import main

if __name__ == "__main__":
    sys.exit(main())
