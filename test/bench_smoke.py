"""Running a benchmark of bench/ in its smoke mode (tiny sizes, seconds), as `make bench` would."""

import os
from pathlib import Path
import re
import subprocess
import sys

REPOSITORY = Path(__file__).resolve().parents[1]


def assert_smoke_run_prints(name, *patterns, timeout=240):
    """Run `python -m bench.<name> --smoke`; assert it ends well, printing each pattern."""
    result = subprocess.run([sys.executable, '-m', f'bench.{name}', '--smoke'], cwd=REPOSITORY,
                            capture_output=True, text=True, timeout=timeout,
                            env=dict(os.environ, SDL_VIDEODRIVER='dummy'))
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    for pattern in patterns:
        assert re.search(pattern, result.stdout, re.MULTILINE), (
            f'bench.{name}: no line matching {pattern!r} in:\n{result.stdout[-2000:]}')
    return result.stdout
