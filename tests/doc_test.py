#!/usr/bin/env python3
"""Runs the command blocks of the manual's pages and checks their output against the page.

Usage:
    tests/doc_test.py --gyrocomp build/gyrocomp [--update] [PAGE.md ...]

With no pages, every page under docs/guides/ plus docs/index.md is run, in name order.

Format of a page (docs/guides/*.md):
  * A fenced block whose info string is ``console`` is run. Each line starting with ``$ `` is a
    command (run by bash in the page's working directory, with the gyrocomp under test first on
    PATH and ``$SHARED`` set to ../shared when it exists). The lines after a command, up to the
    next ``$ `` line, are its expected output (stdout and stderr together).
  * Every page runs in a fresh temporary directory; its files persist from block to block.
  * ``<!-- doctest: setup`` ... ``-->``: commands (one per line) run before the next block, not
    shown on the page (for instance a simulated log standing in for the reader's own).
  * ``<!-- doctest: skip -->`` right before a block: the block is not run (real user files).
  * Comparison, line by line after collapsing runs of spaces: the text between numbers must be
    equal and each number must agree within a relative 2 % (absolute 1e-9 near zero), because the
    figures come from seeded simulations whose last digits may move with the compiler or CPU; a
    line holding only ``...`` matches any number of lines (none included).
  * ``--update`` rewrites each block's expected output with what the commands print now.
Exit status: 0 when every block matches, 1 otherwise (each mismatch printed with page and line).
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REL_TOL = 0.02
ABS_TOL = 1e-9
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
ROOT = Path(__file__).resolve().parent.parent


class Block:
    """One console block: its line span in the page and its commands with expected outputs."""

    def __init__(self, start, end, setup, skip):
        self.start = start  # index of the opening fence line
        self.end = end  # index of the closing fence line
        self.setup = setup  # hidden commands run first
        self.skip = skip
        self.commands = []  # [(command, [expected lines])]


def parse_page(lines):
    blocks, setup, skip, i = [], [], False, 0
    while i < len(lines):
        line = lines[i].rstrip("\n")
        if line.strip() == "<!-- doctest: skip -->":
            skip = True
        elif line.strip().startswith("<!-- doctest: setup"):
            i += 1
            while i < len(lines) and lines[i].strip() != "-->":
                if lines[i].strip():
                    setup.append(lines[i].strip())
                i += 1
        elif line.strip() == "```console":
            start = i
            i += 1
            body = []
            while i < len(lines) and lines[i].rstrip("\n") != "```":
                body.append(lines[i].rstrip("\n"))
                i += 1
            block = Block(start, i, setup, skip)
            for b in body:
                if b.startswith("$ "):
                    block.commands.append((b[2:], []))
                elif block.commands:
                    block.commands[-1][1].append(b)
            blocks.append(block)
            setup, skip = [], False
        i += 1
    return blocks


def numbers_match(expected, actual):
    e_parts, a_parts = NUMBER.split(expected), NUMBER.split(actual)
    e_nums, a_nums = NUMBER.findall(expected), NUMBER.findall(actual)
    if e_parts != a_parts or len(e_nums) != len(a_nums):
        return False
    for e, a in zip(e_nums, a_nums):
        ev, av = float(e), float(a)
        if abs(ev - av) > max(ABS_TOL, REL_TOL * max(abs(ev), abs(av))):
            return False
    return True


def lines_match(expected, actual):
    """Matches expected lines (with '...' wildcards) against actual lines."""
    norm = lambda s: " ".join(s.split())
    expected = [norm(x) for x in expected]
    actual = [norm(x) for x in actual]
    memo = {}

    def go(i, j):
        if (i, j) in memo:
            return memo[(i, j)]
        if i == len(expected):
            ok = j == len(actual)
        elif expected[i] == "...":
            ok = any(go(i + 1, k) for k in range(j, len(actual) + 1))
        else:
            ok = j < len(actual) and numbers_match(expected[i], actual[j]) and go(i + 1, j + 1)
        memo[(i, j)] = ok
        return ok

    return go(0, 0)


def run(command, cwd, env):
    p = subprocess.run(["bash", "-c", command], cwd=cwd, env=env, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=600)
    out = p.stdout.splitlines()
    return p.returncode, out


def run_page(page, gyrocomp, update):
    lines = page.read_text().splitlines(keepends=True)
    blocks = parse_page(lines)
    failures = []
    env = dict(os.environ)
    bindir = tempfile.mkdtemp(prefix="gyrocomp-doc-bin-")
    os.symlink(os.path.abspath(gyrocomp), os.path.join(bindir, "gyrocomp"))
    env["PATH"] = bindir + os.pathsep + env.get("PATH", "")
    env["NO_COLOR"] = "1"
    env["COLUMNS"] = "100"
    shared = ROOT.parent / "shared"
    if shared.is_dir():
        env["SHARED"] = str(shared)
    workdir = tempfile.mkdtemp(prefix="gyrocomp-doc-")
    replacements = {}
    try:
        for block in blocks:
            if block.skip:
                continue
            for cmd in block.setup:
                rc, out = run(cmd, workdir, env)
                if rc != 0:
                    failures.append(f"{page}:{block.start + 1}: setup `{cmd}` exited {rc}:\n  " + "\n  ".join(out[-5:]))
            new_body = []
            for cmd, expected in block.commands:
                rc, out = run(cmd, workdir, env)
                new_body.append("$ " + cmd)
                new_body.extend(out)
                if not update and not lines_match(expected, out):
                    failures.append(f"{page}:{block.start + 1}: `{cmd}` (exit {rc}) printed:\n  " + "\n  ".join(out) +
                                    "\nexpected:\n  " + "\n  ".join(expected))
            replacements[block.start] = (block.end, new_body)
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
        shutil.rmtree(bindir, ignore_errors=True)
    if update and replacements:
        out_lines, i = [], 0
        while i < len(lines):
            if i in replacements:
                end, body = replacements[i]
                out_lines.append(lines[i])
                out_lines.extend(b + "\n" for b in body)
                out_lines.append(lines[end])
                i = end + 1
            else:
                out_lines.append(lines[i])
                i += 1
        page.write_text("".join(out_lines))
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gyrocomp", default=str(ROOT / "build" / "gyrocomp"))
    ap.add_argument("--update", action="store_true", help="rewrite the expected outputs")
    ap.add_argument("pages", nargs="*")
    args = ap.parse_args()
    pages = [Path(p) for p in args.pages]
    if not pages:
        pages = [ROOT / "docs" / "index.md"] + sorted((ROOT / "docs" / "guides").glob("*.md"))
    pages = [p for p in pages if p.exists()]
    failures = []
    for page in pages:
        f = run_page(page, args.gyrocomp, args.update)
        print(f"doc_test: {page.relative_to(ROOT) if page.is_absolute() else page}: "
              f"{'updated' if args.update else ('ok' if not f else str(len(f)) + ' mismatch(es)')}")
        failures.extend(f)
    for f in failures:
        print(f, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
