"""A student's own control law, as doc/python.md writes it, graded by grade_lab: PASS."""

from pathlib import Path
import re
import sys

from grade_runs import grade, write_course

PAGE = Path(__file__).resolve().parents[2] / 'doc' / 'python.md'


def test_the_python_pages_own_law_is_a_controller_grade_lab_passes(tmp_path):
    [block] = [block for block in re.findall(r'```python\n(.*?)```', PAGE.read_text(), re.DOTALL)
               if 'drive(my_law)' in block]
    script = tmp_path / 'my_controller.py'
    script.write_text(block)
    courses = tmp_path / 'courses'
    write_course(courses, 'turn_and_go', '2.5 2.0 0.0\n2.5 3.0 90.0', time_limit=40)
    result = grade('--courses', courses, '--lockstep', '--real-time-factor', 0, '--report',
                   tmp_path / 'report', '--', sys.executable, script, '{waypoints}',
                   cwd=tmp_path, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    assert re.search(r'^turn_and_go +PASS', result.stdout, re.MULTILINE), result.stdout
