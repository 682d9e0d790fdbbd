#!/usr/bin/python3
"""The C++ sources are formatted by the committed .clang-format (ctest Format).

Runs `clang-format --dry-run --Werror` on every .cpp/.hpp/.h under src/, tests/ and bench/
(tracked by git where the tree is a git checkout, else every such file on disk) and exits 1
listing the files that would change. Fix them with `make format`. clang-format 14 (Debian 12's)
is the reference: another major version may format differently.

    check_format.py [ROOT]   (default: this repository)
"""
import pathlib
import shutil
import subprocess
import sys

FOLDERS = ("src", "tests", "bench")
SUFFIXES = (".cpp", ".hpp", ".h")


def sources(root):
    try:
        out = subprocess.run(["git", "-C", str(root), "ls-files", "--", *FOLDERS], check=True,
                             capture_output=True, text=True).stdout.split()
        files = [root / f for f in out]
    except (OSError, subprocess.CalledProcessError):
        files = [p for folder in FOLDERS for p in (root / folder).rglob("*")]
    return sorted(p for p in files if p.suffix in SUFFIXES and p.is_file())


def main(root):
    tool = shutil.which("clang-format")
    if tool is None:
        sys.exit("check_format: clang-format not found (Debian package clang-format; `make deps` installs it)")
    # One clang-format for every file; each violation it prints starts with the file's path.
    files = [str(p) for p in sources(root)]
    r = subprocess.run([tool, "--dry-run", "--Werror", *files], capture_output=True, text=True)
    flagged = {line.split(":", 1)[0] for line in r.stderr.splitlines() if "[-Wclang-format-violations]" in line}
    bad = sorted(str(pathlib.Path(f).relative_to(root)) for f in flagged)
    if r.returncode and not bad:
        sys.exit(f"check_format: clang-format failed: {r.stderr.strip()[:300]}")
    for b in bad:
        print(f"check_format: {b} is not formatted (make format)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(pathlib.Path(sys.argv[1]).resolve() if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parents[1]))
