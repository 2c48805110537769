"""A disk that fills up: files written through it take so many bytes, then refuse."""

import errno
import io
import os

from simple_robot_control import bag


class NearlyFullDisk(io.FileIO):
    """A file on a disk with room for limit bytes, which then refuses as a full disk does."""

    limit = 16 << 10

    def write(self, data):
        room = self.limit - self.tell()
        if room <= 0:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return super().write(bytes(data[:room]))


def fill_up_after(monkeypatch, limit):
    """Make every bag written from now on sit on a disk with room for limit bytes."""
    disk = type('Disk', (NearlyFullDisk,), {'limit': limit})
    monkeypatch.setattr(bag, 'open', lambda path, mode: io.BufferedWriter(disk(path, mode)),
                        raising=False)
