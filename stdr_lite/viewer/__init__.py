"""stdr_viewer: a live picture of the world in a window (pygame)."""
