#!/usr/bin/env python3
"""Runs a command on a virtual display of its own and exits with the command's status.

    python3 tools/headless.py [--size WIDTHxHEIGHT] COMMAND [ARGUMENT ...]

The display is an Xvfb server that picks a free display number itself (-displayfd), so any number of
these can run at once; the server is stopped when the command ends. The status is always the
command's own (128 + the signal's number when a signal ended it), or 1 with one line on stderr when
the display could not be started: nothing of the display's own housekeeping stands in for it.

Tests that open many windows one after another import `Display` instead: one server for all of
them, since every server start compiles a keymap (xkbcomp), most of a short run's cost.
"""
import os
import re
import signal
import subprocess
import sys

USAGE = "usage: headless.py [--size WIDTHxHEIGHT] COMMAND [ARGUMENT ...]"
START_SECONDS = 30


def start_display(size):
    """Starts Xvfb; returns (the server's process, its display name) or (None, why)."""
    read_end, write_end = os.pipe()
    try:
        server = subprocess.Popen(["Xvfb", "-displayfd", str(write_end), "-screen", "0", f"{size}x24",
                                   "-nolisten", "tcp"], pass_fds=(write_end,),
                                  stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    except FileNotFoundError:
        os.close(read_end)
        os.close(write_end)
        return None, "Xvfb is not installed (Debian package xvfb)"
    os.close(write_end)
    number = b""
    with os.fdopen(read_end, "rb") as announced:  # Xvfb writes the number and a newline once it listens
        while not number.endswith(b"\n"):
            byte = announced.read(1)
            if not byte:
                break
            number += byte
    if not number.strip().isdigit():
        server.kill()
        why = server.communicate()[1].decode(errors="replace").strip().splitlines()
        return None, "Xvfb did not start" + (f": {why[-1]}" if why else "")
    server.stderr.close()  # its warnings are of no use to the command's caller
    return server, f":{number.strip().decode()}"


class Display:
    """A virtual display that outlives the commands run on it:

        with Display() as display:
            subprocess.run(command, env=display.environment())

    Raises RuntimeError with the reason when the server cannot start."""

    def __init__(self, size="1280x720"):
        self.size = size
        self.server = None
        self.name = None

    def __enter__(self):
        self.server, self.name = start_display(self.size)
        if self.server is None:
            raise RuntimeError(f"headless: {self.name}")
        return self

    def __exit__(self, *exc):
        self.server.terminate()
        self.server.wait()
        return False

    def environment(self, base=None):
        """The environment a command on this display runs with (os.environ's, or base's)."""
        return {**(os.environ if base is None else base), "DISPLAY": self.name}


def main(argv):
    size = "1280x720"
    if argv[:1] == ["--size"]:
        if len(argv) < 2 or not re.fullmatch(r"[1-9]\d*x[1-9]\d*", argv[1]):
            print(f"error: --size expects WIDTHxHEIGHT such as 1280x720, got '{' '.join(argv[1:2])}'", file=sys.stderr)
            return 2
        size, argv = argv[1], argv[2:]
    if not argv or argv[0].startswith("-"):
        print(USAGE, file=sys.stderr)
        return 2
    server, display = start_display(size)
    if server is None:
        print(f"headless: {display}", file=sys.stderr)
        return 1
    try:
        command = subprocess.Popen(argv, env={**os.environ, "DISPLAY": display})
    except OSError as e:
        server.terminate()
        server.wait()
        print(f"headless: cannot run {argv[0]}: {e.strerror}", file=sys.stderr)
        return 127
    # A signal that would end this process ends the command first, and then the display.
    for number in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(number, lambda received, frame: command.send_signal(received))
    try:
        status = command.wait()
    finally:
        server.terminate()
        server.wait()
    return 128 - status if status < 0 else status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
