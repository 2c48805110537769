"""The GitHub Classroom workflow of doc/grading.md asks of grade_lab what grade_lab takes."""

from pathlib import Path
import shlex

from lab_grader.grade_lab import parse
import yaml

WORKFLOW = Path(__file__).resolve().parents[2] / 'examples' / 'classroom.yml'


def steps():
    workflow = yaml.safe_load(WORKFLOW.read_text())
    [job] = workflow['jobs'].values()
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
