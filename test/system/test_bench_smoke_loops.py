"""The benchmarks of the control law, the viewer and learning run and print their figures."""

import re

from bench_smoke import assert_smoke_run_prints


def test_the_controller_bench_prints_its_ratios_to_the_optimum():
    assert_smoke_run_prints(
        'controller', r'^waypoint_controller +dt 0\.05 +\d+\.\d%( +\d+\.\d{3}){4}',
        r'^rotate-drive-rotate +dt 0\.05 ', r'^planning per waypoint: median \d+\.\d\d ms')


def test_the_optimum_bench_prints_its_ratios_to_the_lower_bound():
    assert_smoke_run_prints('optimum', r'^chained optimum +median \d\.\d{3} +p90 \d\.\d{3}',
                            r'^replay finished \d+\.\d% of the courses')


def test_the_viewer_bench_prints_its_rate_against_the_viewers():
    assert_smoke_run_prints('viewer', r"frames per second: \d+\.\dx the viewer's own rate")


def test_the_learning_bench_prints_the_vector_against_the_single_env():
    assert_smoke_run_prints(
        'learning', r'^waypoint_lab/Waypoints-v0, one robot, 64-ray laser: median [\d,]+ steps '
        r'per CPU-second', r"robot-steps per CPU-second .*: \d+\.\dx the single environment's "
        r'steps/s \(rounds: [\d.]+ to [\d.]+; target >= 20x: (met|missed)\)',
        r'^a step of the single environment, \d+ us of CPU: world \d+, laser \d+, observation '
        r'\d+, goal sets and reward \d+, commands \d+, environment and wrappers -?\d+$')


def test_the_courseworks_bench_prints_the_reference_answers_figures():
    assert_smoke_run_prints(
        'courseworks', r'^plus_room_mapping +PASS  agreement 1\.000, coverage 0\.9\d\d, ',
        r'^plus_room_planning +PASS  path 0\.9\d\dx the shortest, clearance \d\.\d\dx the radius;'
        r' \d+\.\d s sim, \d+x real time in CPU time$')


def test_the_grading_bench_prints_sealed_against_unsealed_grading():
    output = assert_smoke_run_prints('grading', r'^--sandbox none +[0-9.]+ s wall',
                                     r'^rotations +PASS ')
    if '--sandbox namespaces' in output:
        assert re.search(r'^sealed / unsealed wall time: [0-9.]+ \(target at most 1\.2',
                         output, re.MULTILINE), output
