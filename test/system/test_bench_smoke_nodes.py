"""The benchmarks of the running nodes (loop, requests, recorder) run and print their figures."""

import re

from bench_smoke import assert_smoke_run_prints

FIGURE = r'\d+\.\d+x'


def test_the_realtime_bench_prints_the_loop_against_its_ceiling():
    assert_smoke_run_prints(
        'realtime', r'^ +10 +[\d,]+ +[\d,]+ +[\d,]+\.\dx$',
        rf'^one process +{FIGURE} +{FIGURE} +\d+\.\d\d ', rf'^two processes +{FIGURE} +{FIGURE} ',
        r"^the demo's run .*: start \d+\.\d\d s \(\d\.\d{3} of the loop\), loop \d+\.\d\d s, "
        r'end \d+\.\d\d s \(\d\.\d{3} of the loop\); wall time \d+\.\d\d s over the loop$',
        rf'the whole stdr_lite node, 10 lab robots, .*: {FIGURE} real time',
        r'^sensors of 10 lab robots .*: \d+\.\d% of one core')


def test_the_requests_bench_prints_each_burst_against_its_target():
    assert_smoke_run_prints(
        'requests', r'^no requests +\d+\.\d ms',
        r'^a 1,000-point hull +\d+\.\d ms +\d+\.\d ms +\d+\.\d\d s +(met|\d+\.\d\dx over)$',
        r'^a 256x256 world +(\d+\.\d|-) ms')


def test_the_recorder_bench_prints_what_it_kept_of_what_was_sent():
    assert_smoke_run_prints('recorder', r'^record_run, 5 robots at 10 Hz: 5 odometry topics, .*: '
                            r'\d\.\d{3} of what was sent recorded$')


def test_the_live_view_bench_keeps_a_reading_clients_share_beside_20_idle_ones():
    """Its smoke mode is the system test at 20 idle clients (the bench runs 200)."""
    output = assert_smoke_run_prints(
        'live_view', r'^foxglove_live, a reading client on /clock: \d\.\d{3} of the ticks alone, '
        r'\d\.\d{3} beside 20 idle clients: \d+\.\d\d of its share$',
        r'^foxglove_live memory: \d+ MB before, \d+ MB with the idle clients, \d+ MB after')
    alone, beside = map(float, re.search(r'(\d\.\d{3}) of the ticks alone, (\d\.\d{3}) '
                                         'beside', output).groups())
    assert alone > 0.9 and beside > 0.9, output
    before, after = map(int, re.search(r'(\d+) MB before, \d+ MB with the idle clients, '
                                       r'(\d+) MB after', output).groups())
    assert after <= before * 1.1 + 1, output
