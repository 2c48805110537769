"""
The settings of the simulator's process as a whole: made once, in main(), after the node.

They are the interpreter's, not the node's: tests build many simulator nodes in one process
and must not inherit them, and frozen objects are never freed.
"""

import gc
import sys

# How long a thread may hold the interpreter while another waits for it (Python's: 5 ms).
SWITCH_INTERVAL = 0.0005


def settle_for_large_requests() -> None:
    """
    Tune the interpreter for a large request taken beside the simulation loop.

    While the requests' thread converts one (requests.py), the simulator's thread waits for the
    interpreter at each call that lets it go: SWITCH_INTERVAL rather than Python's 5 ms. A
    request of a hundred thousand objects also sets off the garbage collector's full passes,
    each walking every object of the process with the interpreter held (35 to 47 ms here):
    frozen once the node is built, the libraries and the world are left out (about 10 ms).
    """
    sys.setswitchinterval(SWITCH_INTERVAL)
    gc.collect()
    gc.freeze()
