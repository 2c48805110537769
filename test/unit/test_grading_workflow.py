"""The GitHub workflows of doc/grading.md ask of grade_lab what it takes, and leak no token."""

from pathlib import Path
import shlex

from lab_grader.grade_lab import parse
import yaml

EXAMPLES = Path(__file__).resolve().parents[2] / 'examples'
WORKFLOW = EXAMPLES / 'classroom.yml'
CLASS_WORKFLOW = EXAMPLES / 'grade_class.yml'


def steps(path=WORKFLOW, name=None):
    workflow = yaml.safe_load(path.read_text())
    job = workflow['jobs'][name] if name else next(iter(workflow['jobs'].values()))
    return workflow, job['steps']


def test_the_grading_step_is_a_grade_lab_command_line_it_accepts():
    workflow, job_steps = steps()
    assert workflow['env']['ROS_AUTOMATIC_DISCOVERY_RANGE'] == 'LOCALHOST'
    [grade] = [step for step in job_steps if step.get('id') == 'grade']
    [line] = [line for line in grade['run'].splitlines() if line.startswith('grade_lab ')]
    arguments = shlex.split(line.split(' || ')[0])[1:]
    options, command = parse([argument.replace('$RUNNER_TEMP', '/tmp') for argument in arguments])
    assert options.report == 'grade_report' and command[-1] == '{waypoints}'
    assert 'grade_report/classroom.json' in grade['run']


def test_the_reporter_reads_the_result_of_the_grading_step():
    _, job_steps = steps()
    [reporter] = [step for step in job_steps
                  if step.get('uses', '').startswith('classroom-resources/autograding-grading')]
    runner = reporter['with']['runners']
    assert reporter['env'][f'{runner.upper()}_RESULTS'] == '${{ steps.grade.outputs.result }}'


def test_the_students_workflow_holds_no_secret_and_fetches_no_hidden_course():
    text = WORKFLOW.read_text()
    assert 'secrets.' not in text and 'x-access-token' not in text
    assert 'nothing it\n# fetches can be kept from them' in text


def test_the_class_is_graded_from_the_staffs_repository_as_root_sealed_off():
    workflow, job_steps = steps(CLASS_WORKFLOW, 'grade')
    assert workflow['on'] == {'workflow_dispatch': None}
    checkouts = [step for step in job_steps if step.get('uses', '').startswith('actions/checkout')]
    assert all(step['with']['persist-credentials'] is False for step in checkouts)
    [clone] = [step for step in job_steps if 'STUDENTS_TOKEN' in step.get('env', {})]
    # The token goes in a header of the one clone command: never an address or .git/config.
    assert '@github.com' not in clone['run'] and 'http.extraHeader' in clone['run']
    [grade] = [step for step in job_steps if 'grade_lab' in step.get('run', '')]
    assert grade['run'].startswith('sudo ')
    line = ' '.join(grade['run'].split('\\\n')).split(' || ')[0]
    arguments = shlex.split(line.split('grade_lab"', 1)[1])
    options, command = parse([argument.replace('$RUNNER_TEMP', '/tmp') for argument in arguments])
    assert (options.sandbox, options.submissions) == ('namespaces', '/tmp/groups')
    assert command[-1] == '{waypoints}'
