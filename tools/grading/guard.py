"""The write guard: the lab's own files stay as they are, whatever a graded test writes."""
import os
import pathlib
import shutil
import threading
import time


class Guard:
    """Notices when a test writes into the lab's files (what builds and grades: the folders and files
    below), puts them back and keeps what was written in quarantine/ of the build folder. Build
    folders, worksheets and results are not guarded. Thread-safe: parallel graders share one guard."""

    FOLDERS = {"tests", "tools", "framework", "cmake", "assignments", "solutions"}
    FILES = {"CMakeLists.txt", "CMakePresets.json", "lab"}
    SKIP = {".git", "__pycache__"}

    def __init__(self, root, quarantine, skip=()):
        self.root, self.quarantine = pathlib.Path(root), pathlib.Path(quarantine)
        self.skip = [pathlib.Path(s).resolve() for s in skip]
        self.lock = threading.Lock()
        self.files = self._scan()
        self.contents = {p: p.read_bytes() for p in self.files}
        # Tests running now; those that were running when a change was found are suspects and run
        # again alone (no other test at the same time) to find out which one wrote.
        self.cond = threading.Condition()
        self.running, self.suspects, self.alone = set(), set(), None

    def start(self, alone=False):
        token = object()
        with self.cond:
            self.cond.wait_for(lambda: self.alone is None)
            if alone:
                self.alone = token
                self.cond.wait_for(lambda: not self.running)
            self.running.add(token)
        return token

    def finish(self, token):
        """Checks the files after a test. Returns (changed paths, suspect): suspect when the change
        may have come from another test that ran at the same time, so the test must run again alone."""
        with self.cond:
            changed = self.check()
            others = self.running - {token}
            if changed and others:
                self.suspects |= self.running
            suspect = token in self.suspects
            self.suspects.discard(token)
            self.running.discard(token)
            if self.alone is token:
                self.alone = None
            self.cond.notify_all()
        return changed, suspect

    def _skipped(self, path):
        if path.name in self.SKIP or path.name.startswith("build") or path.name.startswith("assignments.backup"):
            return True
        return any(path == s or s in path.parents for s in self.skip)

    def _scan(self):
        found = {}
        stack = [self.root]
        while stack:
            folder = stack.pop()
            try:
                entries = list(os.scandir(folder))
            except OSError:
                continue
            for e in entries:
                p = pathlib.Path(e.path)
                if self._skipped(p.resolve() if e.is_symlink() else p):
                    continue
                if e.is_dir(follow_symlinks=False):
                    if folder != self.root or e.name in self.FOLDERS:
                        stack.append(p)
                elif e.is_file(follow_symlinks=False) and (folder != self.root or e.name in self.FILES):
                    st = e.stat(follow_symlinks=False)
                    found[p] = (st.st_mtime_ns, st.st_size)
        return found

    def check(self):
        """Puts back what changed since the last check; returns the changed paths (relative)."""
        with self.lock:
            now = self._scan()
            changed = []
            stamp = self.quarantine / time.strftime("%Y%m%d-%H%M%S")
            for p in sorted(set(now) | set(self.files)):
                if self.files.get(p) == now.get(p):
                    continue
                if p in now and p in self.contents and p.read_bytes() == self.contents[p]:
                    continue  # touched, not changed
                rel = p.relative_to(self.root)
                if p in now:  # what was written is kept aside, never lost
                    (stamp / rel).parent.mkdir(parents=True, exist_ok=True)
                    shutil.move(str(p), str(stamp / rel))
                    del now[p]
                if p in self.contents:
                    p.parent.mkdir(parents=True, exist_ok=True)
                    p.write_bytes(self.contents[p])
                    st = p.stat()
                    now[p] = (st.st_mtime_ns, st.st_size)
                changed.append(str(rel))
            # The next check compares with this scan (and what was put back), never with a later
            # one: a test still running may write after the scan, and that must not go unseen.
            self.files = now
            return changed
