"""Every command the README and the site's pages document works as written.

Convention: a fenced code block tagged ``bash`` in ``README.md`` or ``docs/*.md`` holds
commands a user types, one per line (``&&`` chains them; ``# ...`` after a command is a
comment), run from the root of a clone. Commands shown for reading only go in ``text``
blocks. The commands deliberately not run are listed in :data:`NOT_RUN`, each with its
reason.

Opt-in (``python -m pytest --commands -m commands``): each block runs in a fresh copy of
the repository (the files git tracks or would track, as a clone has them, uncommitted
edits included) with a fresh virtual environment: a block that creates ``.venv`` itself
runs exactly as written; any other block first gets what the README's reproduce command
does before it (``python3 -m venv .venv && . .venv/bin/activate && pip install -e .``),
since that is where a reader stands. The test asserts exit status 0 of every command and
shows the failing command with the end of its output. Without ``--commands`` the tests
are reported as skipped with that reason (``-ra``).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = ("README.md", *sorted(f"docs/{p.name}" for p in (ROOT / "docs").glob("*.md")))
FENCE = re.compile(r"^(\s*)```(\S*)\s*$")
#: the venv a block without its own starts from: the README's reproduce command up to
#: ``debench reproduce``
PRELUDE = ("python3 -m venv .venv", ". .venv/bin/activate", "pip install -e .")
#: one block's commands may take this long (a default reproduce on a loaded 2-core machine
#: with the install before it)
TIMEOUT_S = 3600

#: Documented commands deliberately not run here, with the reason.
NOT_RUN = {
    "python -m pytest -n auto": (
        "the whole verification suite (about 2,000 tests, tens of minutes on two cores), "
        "of which this test is an opt-in member; CI runs it as documented, and the install "
        "before it in the same line is run here"),
    "git checkout A": "A and B are placeholders for two commits the reader compares",
    "git checkout B": "A and B are placeholders for two commits the reader compares",
    "python -m pytest benchmarks --benchmark-autosave": (
        "one step of the comparison of two commits A and B (placeholders)"),
    "pytest-benchmark compare 0001 0002 --group-by=name --columns=min,median,stddev": (
        "compares the two saved runs of the steps above, which are not run"),
}


@dataclass(frozen=True)
class Block:
    """A fenced ``bash`` block: where it is and its commands (``&&`` chains split)."""

    document: str
    line: int
    commands: tuple[str, ...]

    @property
    def id(self) -> str:
        return f"{self.document}:{self.line}"


def _strip_comment(line: str) -> str:
    """The command of a line without a trailing ``  # comment`` (never inside quotes: the
    documented commands quote no ``#``)."""
    return re.sub(r"(^|\s)#.*$", "", line).strip()


def command_blocks(document: str) -> list[Block]:
    """The ``bash`` blocks of ``document`` (relative to the repository root), in order."""
    blocks, inside, start, lines = [], None, 0, []
    for k, line in enumerate((ROOT / document).read_text(encoding="utf-8").splitlines(), 1):
        m = FENCE.match(line)
        if inside is None and m and m.group(2):
            inside, start, lines = m.group(2), k, []
        elif inside is not None and m and not m.group(2):
            if inside == "bash":
                cmds = [c.strip() for text in lines for c in _strip_comment(text).split("&&")]
                blocks.append(Block(document, start, tuple(c for c in cmds if c)))
            inside = None
        elif inside is not None:
            lines.append(line)
    return blocks


def all_blocks() -> list[Block]:
    """Every block of :data:`DOCUMENTS`; a block repeated word for word (the README's
    commands on the getting-started page) once, where it first appears."""
    seen, out = set(), []
    for doc in DOCUMENTS:
        for b in command_blocks(doc):
            if b.commands not in seen:
                seen.add(b.commands)
                out.append(b)
    return out


def test_documented_commands_are_found_and_every_skip_is_documented():
    """The convention finds the README's commands (reproduce, test, docs build), and every
    entry of NOT_RUN is a documented command (no stale reasons)."""
    blocks = all_blocks()
    commands = {c for b in blocks for c in b.commands}
    assert "debench reproduce" in commands
    assert any(c.startswith("sphinx-build") for c in commands)
    assert set(NOT_RUN) <= commands, set(NOT_RUN) - commands
    assert all(reason.strip() for reason in NOT_RUN.values())


def _clean_env(home: Path) -> dict[str, str]:
    """The environment of a reader's shell: no venv of ours active, one thread per process."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("VIRTUAL_ENV", "PYTHONPATH", "DEBENCH_DATA_DIR", "PYTHONHOME")}
    ours = str(Path(sys.prefix) / "bin")
    env["PATH"] = os.pathsep.join(p for p in env.get("PATH", "").split(os.pathsep)
                                  if p != ours)
    env.setdefault("OMP_NUM_THREADS", "1")
    env["MPLCONFIGDIR"] = str(home / "mpl")
    return env


def _clone(dest: Path) -> Path:
    """The files of the working tree that git tracks or would track, copied to ``dest``."""
    listed = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT,
                            capture_output=True, check=True).stdout.decode().split("\0")
    for rel in filter(None, listed):
        src = ROOT / rel
        if src.is_file():
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / rel)
    return dest


def script(block: Block) -> str:
    """The bash script that runs ``block``: the prelude unless the block makes its venv,
    then each command not in :data:`NOT_RUN`, each echoed before it runs."""
    cmds = list(block.commands)
    if not any(c.startswith("python3 -m venv") for c in cmds):
        cmds = [*PRELUDE, *cmds]
    lines = ["set -e"]
    for c in cmds:
        if c in NOT_RUN:
            lines.append(f"echo {_quote('# not run: ' + c)}")
            continue
        lines += [f"echo {_quote('+ ' + c)}", c]
    return "\n".join(lines) + "\n"


def _quote(text: str) -> str:
    import shlex

    return shlex.quote(text)


@pytest.mark.commands
@pytest.mark.parametrize("block", all_blocks(), ids=lambda b: b.id)
def test_documented_command_block_runs_in_a_fresh_clone_and_venv(block, tmp_path):
    """Each documented block, run as a reader would in a fresh clone and venv, exits 0."""
    if all(c in NOT_RUN for c in block.commands):
        pytest.skip("every command of this block is in NOT_RUN: "
                    + "; ".join(sorted(set(NOT_RUN[c] for c in block.commands))))
    import signal

    clone = _clone(tmp_path / "clone")
    # its own process group: a timeout ends the block's commands and their pool processes
    proc = subprocess.Popen(["bash", "-c", script(block)], cwd=clone, env=_clean_env(tmp_path),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        out, err = proc.communicate(timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        ran = [line for line in out.splitlines() if line.startswith("+ ")]
        pytest.fail(f"{block.id}: `{ran[-1][2:] if ran else '?'}` still running after "
                    f"{TIMEOUT_S} s (machine load {os.getloadavg()[0]:.1f}); ended",
                    pytrace=False)
    ran = [line for line in out.splitlines() if line.startswith("+ ")]
    assert proc.returncode == 0, (
        f"{block.id}: `{ran[-1][2:] if ran else '?'}` exited {proc.returncode}:\n"
        f"{out[-3000:]}\n{err[-3000:]}")
