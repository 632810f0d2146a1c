"""Similarity of the hook files handed in by a batch of submissions: which pairs to look at.

Every hook file first loses the lines that stand in the stub as handed out (assignments/), so the
skeleton every student starts from counts for nothing and an untouched stub drops out. What is left
is compared pair by pair with sim_c from Debian's similarity-tester, which compares C tokens:
renaming variables or changing the layout does not hide a copy. The report has one row per pair of
submissions and hook file: how much of the first file's code is found in the second's, in percent.
"""
import csv
import pathlib
import re
import shutil
import subprocess
import tempfile

SIM = "sim_c"
LINE = re.compile(r"^(.*) consists for (\d+) % of (.*) material$")


class SimilarityError(Exception):
    pass


def own_code(text, stub_lines):
    """The lines of a hook file that are not in its stub (blank lines dropped)."""
    return [line for line in text.splitlines() if line.strip() and line.strip() not in stub_lines]


def compare(submissions, hook_files, stubs_dir, threshold=20):
    """submissions: {name: folder holding the hook files}. Returns rows (percent, a, b, hook file),
    most similar first, for every pair whose shared code is at least `threshold` percent of a."""
    if shutil.which(SIM) is None:
        raise SimilarityError("--similarity needs sim_c from the Debian package similarity-tester")
    rows = []
    with tempfile.TemporaryDirectory(prefix="gpl-similarity-") as tmp:
        for hook in hook_files:
            stub = pathlib.Path(stubs_dir) / hook
            stub_lines = {l.strip() for l in stub.read_text(errors="replace").splitlines()} if stub.is_file() else set()
            folder = pathlib.Path(tmp) / pathlib.Path(hook).stem
            folder.mkdir()
            files = {}
            for name, source in sorted(submissions.items()):
                path = pathlib.Path(source) / hook
                if not path.is_file():
                    continue
                kept = own_code(path.read_text(errors="replace"), stub_lines)
                if not kept:
                    continue  # the stub as handed out
                reduced = folder / f"{len(files):04d}.c"
                reduced.write_text("\n".join(kept) + "\n")
                files[str(reduced)] = name
            if len(files) < 2:
                continue
            proc = subprocess.run([SIM, "-p", "-e", "-a", "-s", "-T", f"-t{threshold}", *files], capture_output=True,
                                  text=True)
            if proc.returncode != 0:
                raise SimilarityError(f"{SIM} failed on {hook}: {proc.stderr.strip()}")
            for line in proc.stdout.splitlines():
                m = LINE.match(line.strip())
                if m and m.group(1) in files and m.group(3) in files:
                    rows.append((int(m.group(2)), files[m.group(1)], files[m.group(3)], hook))
    rows.sort(key=lambda r: (-r[0], r[1], r[2], r[3]))
    return rows


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["percent", "submission", "similar_to", "hook_file"])
        out.writerows(rows)


def summary(rows, most=10):
    """The most similar pairs as lines for people."""
    if not rows:
        return "similarity: no pair of submissions shares code beyond the stubs"
    lines = ["most similar (code beyond the stubs, in percent of the first submission's file):"]
    for percent, a, b, hook in rows[:most]:
        lines.append(f"  {percent:3d} %  {a} in {b}  ({hook})")
    return "\n".join(lines)
