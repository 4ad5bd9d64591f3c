"""Run a peer library's adapter on a debench problem and write a complete submission.

    python peers/run.py LIBRARY PROBLEM [--label L] [--out DIR] [-- ADAPTER ARGS]
    python peers/run.py LIBRARY --script FILE [-- ARGS]     # any script of peers/LIBRARY/
    python peers/run.py LIBRARY --env-only                  # build the venv, report it

Run it with the Python that has debench installed (it reads the problem and checks the
result). Library-agnostic: everything specific to a library is in ``peers/LIBRARY/``:

* ``python-version``: one line, the Python the library needs (e.g. ``3.12``);
* ``requirements.txt``: the pinned (``==``) requirements;
* ``<problem_id>.py``: the adapter of that problem.

The venv lives at ``${DEBENCH_PEERS_CACHE:-~/.cache/debench-peers}/LIBRARY-<hash>``, the
hash of the requirements and the Python version, built once (in a temporary folder renamed
into place when the install succeeded, so a failed install leaves nothing behind) and
reused; its install time and size are recorded in ``install.json`` there.

The adapter protocol: the adapter is run as
``VENV/bin/python peers/LIBRARY/PROBLEM.py --problem-json P --out W [--label L] [ARGS]``
with ``P`` the problem's ``debench problems PROBLEM --json`` and ``W`` an empty folder; it
writes ``W/results.csv`` (the file ``debench check`` reads) and ``W/adapter.json``:
``{"code": {...}, "method": {...}, "check": {...}?, "quantity": "..."}`` with the fields of
the submission format's ``[code]``, ``[method]`` and optional ``[check]`` tables. This
script fills in the rest (environment, hardware, timing, the command, the submitter and
date), the checksum and the claimed check outcome, validates the folder with
:func:`debench.reference.submissions.load`, and moves it into place (default
``submissions/PROBLEM/LIBRARY-LABEL/``). One thread per process (OMP/BLAS) unless
``DEBENCH_THREADS`` says otherwise; one MPI rank.
"""

from __future__ import annotations

import argparse
import datetime as dt
import hashlib
import json
import os
import platform
import resource
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PEERS = Path(__file__).resolve().parent
REPO = PEERS.parent


class PeerError(RuntimeError):
    """A peer environment or adapter run that failed (never a silent skip)."""


# --------------------------------------------------------------------------- environment
def library_dir(library: str) -> Path:
    d = PEERS / library
    if not (d / "requirements.txt").is_file() or not (d / "python-version").is_file():
        known = sorted(p.name for p in PEERS.iterdir()
                       if (p / "requirements.txt").is_file())
        raise PeerError(f"peers/{library}/ needs requirements.txt and python-version "
                        f"(libraries: {', '.join(known)})")
    return d


def requirements(library: str) -> list[str]:
    """The pinned requirements; PeerError for any line that is not ``name==version``."""
    lines = [ln.split("#", 1)[0].strip()
             for ln in (library_dir(library) / "requirements.txt").read_text().splitlines()]
    reqs = [ln for ln in lines if ln]
    loose = [r for r in reqs if "==" not in r]
    if loose or not reqs:
        raise PeerError(f"peers/{library}/requirements.txt must pin every requirement "
                        f"with ==, got {loose or 'nothing'}")
    return reqs


def find_python(version: str) -> Path:
    """A working interpreter of ``version`` (``3.12``): ``pythonX.Y`` on PATH, else a pyenv
    installation (``$PYENV_ROOT/versions/X.Y.*``); each candidate must run (a pyenv shim
    of a version not selected does not). PeerError naming what was searched."""
    root = Path(os.environ.get("PYENV_ROOT", Path.home() / ".pyenv")) / "versions"
    cands = [Path(h) for h in [shutil.which(f"python{version}")] if h]
    cands += sorted(root.glob(f"{version}.*/bin/python{version}"), reverse=True)
    for cand in cands:
        try:
            r = subprocess.run([str(cand), "-c", "import sys; print(sys.version_info[:2])"],
                               capture_output=True, text=True, timeout=60)
        except (OSError, subprocess.TimeoutExpired):
            continue
        if r.returncode == 0 and r.stdout.strip() == str(tuple(map(int, version.split(".")))):
            return cand
    raise PeerError(f"no working Python {version} found (python{version} on PATH, or "
                    f"{root}/{version}.*; tried {[str(c) for c in cands]}): install it, "
                    f"e.g. `pyenv install {version}`")


def _python_full_version(python: Path) -> str:
    return subprocess.run([str(python), "-c", "import platform; "
                           "print(platform.python_version())"], check=True,
                          capture_output=True, text=True).stdout.strip()


def cache_root() -> Path:
    return Path(os.environ.get("DEBENCH_PEERS_CACHE",
                               Path.home() / ".cache" / "debench-peers"))


def _dir_size(path: Path) -> int:
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file() and not p.is_symlink())


def ensure_env(library: str, *, log=sys.stderr) -> Path:
    """The venv of ``library`` (created from its pinned requirements if absent)."""
    d = library_dir(library)
    want = (d / "python-version").read_text().strip()
    python = find_python(want)
    full = _python_full_version(python)
    reqs = requirements(library)
    key = hashlib.sha256(("\n".join(reqs) + "\npython " + full).encode()).hexdigest()[:12]
    venv = cache_root() / f"{library}-{key}"
    if (venv / "install.json").is_file():
        return venv
    if venv.exists():  # an install that did not finish: start again
        shutil.rmtree(venv)
    cache_root().mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{library}-", dir=cache_root()))
    try:
        print(f"peers: building {venv.name} (Python {full}, {len(reqs)} pinned "
              "requirements)", file=log)
        t0 = time.perf_counter()
        # the venv is created at its final path name inside tmp, then tmp/venv is moved:
        # console scripts hard-code their interpreter path, so build where it will live
        subprocess.run([str(python), "-m", "venv", str(venv)], check=True)
        try:
            pip = [str(venv / "bin" / "python"), "-m", "pip", "install",
                   "--disable-pip-version-check", "--no-input"]
            subprocess.run(pip + reqs, check=True, stdout=log, stderr=subprocess.STDOUT)
        except BaseException:
            shutil.rmtree(venv, ignore_errors=True)
            raise
        seconds = time.perf_counter() - t0
        freeze = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "freeze",
                                 "--all"], check=True, capture_output=True, text=True).stdout
        info = {"library": library, "python": full, "requirements": reqs,
                "freeze": freeze.split(), "install_seconds": round(seconds, 1),
                "size_bytes": _dir_size(venv),
                "built": dt.datetime.now(dt.UTC).isoformat(timespec="seconds")}
        (tmp / "install.json").write_text(json.dumps(info, indent=1))
        os.replace(tmp / "install.json", venv / "install.json")  # marks the venv complete
    except subprocess.CalledProcessError as exc:
        raise PeerError(f"installing peers/{library}/requirements.txt into {venv} failed "
                        f"({exc})") from None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return venv


def env_info(venv: Path) -> dict:
    return json.loads((venv / "install.json").read_text())


def child_env() -> dict:
    threads = os.environ.get("DEBENCH_THREADS", "1")
    env = dict(os.environ)
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                "BLIS_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
        env[var] = threads
    env.pop("PYTHONPATH", None)  # the peer venv sees none of the debench environment
    return env


# --------------------------------------------------------------------------- metadata
def hardware() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    threads = os.environ.get("DEBENCH_THREADS", "1")
    return (f"{cpu}; {os.cpu_count()} cores on the machine, 1 MPI rank and {threads} "
            "thread(s) used")


def submitter() -> str:
    name = os.environ.get("DEBENCH_SUBMITTER")
    if name:
        return name
    try:
        name = subprocess.run(["git", "-C", str(REPO), "config", "user.name"],
                              capture_output=True, text=True).stdout.strip()
    except OSError:
        name = ""
    return name or "unknown (set DEBENCH_SUBMITTER)"


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int | float):
        return repr(float(v)) if isinstance(v, float) else str(v)
    if isinstance(v, list):
        return "[\n" + "".join(f"  {_toml_value(x)},\n" for x in v) + "]"
    return json.dumps(str(v), ensure_ascii=False)  # a JSON string is a TOML basic string


def to_toml(meta: dict) -> str:
    """TOML text of the metadata (top-level keys, then one level of tables)."""
    out = [f"{k} = {_toml_value(v)}" for k, v in meta.items() if not isinstance(v, dict)]
    for k, v in meta.items():
        if isinstance(v, dict):
            out += ["", f"[{k}]"] + [f"{kk} = {_toml_value(vv)}" for kk, vv in v.items()]
    return "\n".join(out) + "\n"


def _git_commit() -> str:
    r = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short=12", "HEAD"],
                       capture_output=True, text=True)
    return r.stdout.strip() or "unknown"


# --------------------------------------------------------------------------- run
def run_adapter(library: str, problem: str, *, label: str, out: Path | None,
                adapter_args: list[str], command: str, log=sys.stderr) -> Path:
    """Run ``peers/LIBRARY/PROBLEM.py`` in the library's venv and write the submission
    folder; returns its path."""
    from debench.reference import problems, problems_reference

    adapter = library_dir(library) / f"{problem}.py"
    if not adapter.is_file():
        raise PeerError(f"no adapter {adapter.relative_to(REPO)} for problem {problem}")
    prob = problems.get(problem)
    venv = ensure_env(library, log=log)
    info = env_info(venv)
    out = Path(out) if out else REPO / "submissions" / problem / f"{library}-{label}"
    work = Path(tempfile.mkdtemp(prefix=f"{library}-{problem}-"))
    try:
        pj = work / "problem.json"
        pj.write_text(json.dumps(problems_reference.reference_json(prob)))
        result_dir = work / "out"
        result_dir.mkdir()
        cmd = [str(venv / "bin" / "python"), str(adapter), "--problem-json", str(pj),
               "--out", str(result_dir), "--label", label, *adapter_args]
        print(f"peers: {shlex.join(cmd)}", file=log)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, env=child_env(), cwd=REPO, stdout=log,
                              stderr=subprocess.STDOUT)
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if proc.returncode != 0:
            raise PeerError(f"adapter {adapter.relative_to(REPO)} failed (exit "
                            f"{proc.returncode}); nothing written to {out}")
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        return write_submission(result_dir, problem, info=info, command=command, wall=wall,
                                cpu=cpu, adapter=str(adapter.relative_to(REPO)), out=out,
                                log=log)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def write_submission(result_dir: Path, problem: str, *, info: dict, command: str,
                     wall: float, cpu: float, adapter: str, out: Path, log=sys.stderr) -> Path:
    """The submission folder from an adapter's output (``results.csv`` and
    ``adapter.json`` in ``result_dir``): metadata completed (``info``: the venv's install
    record), checksum, claimed outcome; validated in a staging folder, then moved to
    ``out`` (replacing an older one only once the new one is complete)."""
    from debench.reference import problems, submissions

    prob = problems.get(problem)
    result_dir = Path(result_dir)
    produced = json.loads((result_dir / "adapter.json").read_text())
    results = result_dir / "results.csv"
    if not results.is_file():
        raise PeerError(f"the adapter wrote no results.csv in {result_dir}")
    meta = {
        "schema_version": 1, "problem": problem,
        "quantity": produced.get("quantity", prob.quantities[0].name),
        "results": "results.csv", "results_sha256": submissions.sha256_of(results),
        "code": produced["code"],
        "submitter": {"name": submitter(),
                      "date": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
                      "affiliation": f"debench peers/run.py (debench commit "
                                     f"{_git_commit()})"},
        "method": produced["method"],
        "environment": {"python": info["python"],
                        "platform": platform.platform(),
                        "hardware": hardware(),
                        "requirements": [r for r in info["freeze"] if "==" in r]},
        "run": {"command": command, "wall_seconds": round(wall, 2),
                "cpu_seconds": round(cpu, 2), "adapter": adapter},
    }
    if produced.get("check"):
        meta["check"] = dict(produced["check"])
    stage = Path(tempfile.mkdtemp(prefix=".submission-", dir=result_dir))
    shutil.copy2(results, stage / "results.csv")
    (stage / submissions.METADATA_NAME).write_text(to_toml(meta), encoding="utf-8")
    try:
        outcome = submissions.check(submissions.load(stage))
    except submissions.SubmissionError as exc:
        raise PeerError(f"the adapter's results cannot be judged: {exc}") from None
    meta.setdefault("check", {})["claimed"] = "match" if outcome.passed else "mismatch"
    (stage / submissions.METADATA_NAME).write_text(to_toml(meta), encoding="utf-8")
    submissions.load(stage)  # the final folder validates
    print(f"peers: {outcome.verdict.summary()}", file=log)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    old = out.with_name(f".{out.name}.old")
    if out.exists():
        os.replace(out, old)
    shutil.move(str(stage), str(out))
    shutil.rmtree(old, ignore_errors=True)
    print(f"peers: wrote {out} (wall {wall:.1f} s, cpu {cpu:.1f} s)", file=log)
    return out


def run_script(library: str, script: str, args: list[str], log=sys.stderr) -> int:
    """Run any script of ``peers/LIBRARY/`` in the library's venv (e.g. a comparison with a
    published example); its exit code."""
    path = library_dir(library) / script
    if not path.is_file():
        raise PeerError(f"no script peers/{library}/{script}")
    venv = ensure_env(library, log=log)
    cmd = [str(venv / "bin" / "python"), str(path), *args]
    print(f"peers: {shlex.join(cmd)}", file=log)
    return subprocess.run(cmd, env=child_env(), cwd=REPO).returncode


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = []
    if "--" in argv:
        i = argv.index("--")
        argv, extra = argv[:i], argv[i + 1:]
    p = argparse.ArgumentParser(prog="peers/run.py", description=__doc__.split("\n\n")[0])
    p.add_argument("library")
    p.add_argument("problem", nargs="?")
    p.add_argument("--label", default="default", help="variant name (folder LIBRARY-LABEL)")
    p.add_argument("--out", help="submission folder (default submissions/PROBLEM/LIBRARY-LABEL)")
    p.add_argument("--script", help="run this script of peers/LIBRARY/ in the venv instead")
    p.add_argument("--env-only", action="store_true", help="build/reuse the venv and print "
                   "its install record")
    a = p.parse_args(argv)
    try:
        if a.env_only:
            print(json.dumps(env_info(ensure_env(a.library)), indent=1))
            return 0
        if a.script:
            return run_script(a.library, a.script, extra)
        if not a.problem:
            p.error("PROBLEM is required (or --script / --env-only)")
        command = shlex.join(["python", "peers/run.py", *argv] + (["--", *extra] if extra
                                                                  else []))
        run_adapter(a.library, a.problem, label=a.label, out=a.out, adapter_args=extra,
                    command=command)
        return 0
    except PeerError as exc:
        print(f"peers/run.py: error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
