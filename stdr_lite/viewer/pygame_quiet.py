"""pygame, imported without the greeting it prints on stdout (it would pollute piped output)."""

import os

os.environ.setdefault('PYGAME_HIDE_SUPPORT_PROMPT', '1')

import pygame  # noqa: E402,I100  (the variable above must be set before the import)

__all__ = ['pygame']
