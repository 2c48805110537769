"""The documentation names every node parameter and its examples load: docs and code agree."""

from pathlib import Path
import re
import subprocess
import sys

from installed_executables import parameter_table, PARAMETER_TABLES
import pytest
from simple_robot_control.share import BUNDLED_RESOURCES, shared_file
from stdr_lite.core.robot_description import load_robot

REPOSITORY = Path(__file__).resolve().parents[2]
PAGES = [REPOSITORY / 'README.md', *sorted(REPOSITORY.glob('doc/*.md'))]
DOCUMENTATION = '\n'.join(path.read_text() for path in PAGES)


@pytest.mark.parametrize('executable', PARAMETER_TABLES)
def test_every_parameter_has_a_row_in_the_documentation(executable):
    missing = [spec.name for spec in parameter_table(executable)
               if f'| `{spec.name}` |' not in DOCUMENTATION]
    assert not missing, f'the documentation lacks rows for {missing}'


def test_the_readme_links_every_page():
    readme = (REPOSITORY / 'README.md').read_text()
    pages = sorted(path.name for path in REPOSITORY.glob('doc/*.md'))
    assert pages and all(f'(doc/{page})' in readme for page in pages)


def examples(page, language):
    """Return the text of each fenced block of language on a page."""
    return re.findall(rf'```{language}\n(.*?)```', (REPOSITORY / page).read_text(), re.DOTALL)


@pytest.mark.parametrize('page', ['README.md', 'doc/robot_files.md'])
def test_the_robot_file_examples_load_as_shown(page, tmp_path):
    """Each XML and YAML robot example loads, its includes found in the bundled resources."""
    texts = examples(page, 'xml') + [text for text in examples(page, 'yaml')
                                     if 'robots:' not in text]
    assert texts
    for number, text in enumerate(texts):
        path = tmp_path / f'example{number}.{"xml" if text.startswith("<") else "yaml"}'
        path.write_text(text)
        robot = load_robot(path, (shared_file(*BUNDLED_RESOURCES),))
        assert robot.lasers or robot.sonars


def test_the_python_examples_run_as_shown(tmp_path, monkeypatch):
    """The README's Python blocks run as they stand, in a fresh folder."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv('SDL_VIDEODRIVER', 'dummy')
    blocks = examples('README.md', 'python')
    assert len(blocks) == 2
    for block in blocks:
        exec(compile(block, 'README.md', 'exec'), {})
    assert (tmp_path / 'path.png').stat().st_size > 0


def test_every_benchmark_make_bench_runs_has_a_smoke_mode_and_the_helpers_say_they_are_not():
    makefile = (REPOSITORY / 'Makefile').read_text()
    benches = re.findall(r'\$\(PYTHON\) -m bench\.(\w+)', makefile)
    assert len(benches) >= 8
    for name in benches:
        assert "'--smoke'" in (REPOSITORY / 'bench' / f'{name}.py').read_text(), name
    for helper in ('round_trip', 'odometry_listener'):
        assert 'a helper process' in (REPOSITORY / 'bench' / f'{helper}.py').read_text()


@pytest.mark.skipif(Path(sys.prefix).resolve() != (REPOSITORY / '.venv').resolve(),
                    reason="make's .venv is not the suite's Python (colcon test runs the suite "
                    'from its install tree)')
def test_make_reinstalls_the_package_only_when_its_sources_changed():
    # The suite runs after make install: nothing is left for it to do (make -q says so).
    result = subprocess.run(['make', '-q', 'install'], cwd=REPOSITORY, capture_output=True,
                            text=True, timeout=60)
    assert result.returncode == 0, 'make install would reinstall an unchanged package'
