"""Interactive tools for driving the simulator by hand."""
