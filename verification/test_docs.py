"""The documentation site: it builds with no warning, every page is there, every internal
link resolves, and a headless browser renders it.

Opt-in (``python -m pytest --docs -m docs``): the build runs every example script and the
whole catalogue (about a minute on two cores). Opted in, a missing Sphinx or Chromium
fails with how to install it; nothing is skipped.

* the build: ``sphinx-build -W --keep-going -n -b html`` (warnings are errors, nitpicky
  cross-references), into a temporary directory;
* pages: one per reference problem, per curated dataset and per public module of
  ``debench.models``; every public function and class of those modules has an entry;
* internal links: every relative ``href``/``src`` of every page names a file of the site,
  and its ``#fragment`` an id of that file (the site is built offline, so ``-b linkcheck``
  of external links cannot run here);
* browser: Debian's Chromium, headless, opens the index and a problem page with a figure
  from a local HTTP server and reports each page's title and whether every ``<img>``
  loaded (``naturalWidth > 0``);
* layout: the same browser opens every page of the site 1400 px wide and reports each
  table wider than the room it has (the article column, or the theme's scroll container)
  and each Python repr (``np.float64(``, ``{'``) in the text a reader sees;
* problem data: every reference problem page offers its reference values as JSON (what
  ``debench problems ID --json`` prints) and CSV downloads, and the pages of problems with
  curated submissions show the plot of the reference beside the other codes.
"""

from __future__ import annotations

import functools
import http.server
import importlib
import inspect
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import threading
import time
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

pytestmark = pytest.mark.docs

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
#: the problem page the browser opens: it has curated figures (thesis Fig. 3.7)
PROBLEM_PAGE = "generated/problems/ch3_failure_points.html"
#: seconds the browser may spend loading the pages (virtual time: it ends early when
#: nothing is pending); a page of this site loads locally in well under a second
BROWSER_BUDGET_MS = 20000
#: the window width at which no table of the site may overflow (without the site CSS the errata
#: table showed only its first two columns at this width)
LAYOUT_WIDTH_PX = 1400
#: text that is a Python repr reaching a reader, never data formatted for reading
RAW_REPRS = ("np.float64(", "{'")
#: virtual milliseconds the browser may spend laying out every page of the site
LAYOUT_BUDGET_MS = 300000
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync"]


def _require_sphinx() -> None:
    try:
        import myst_parser  # noqa: F401
        import numpydoc  # noqa: F401
        import pydata_sphinx_theme  # noqa: F401
        import sphinx  # noqa: F401
        import sphinx_gallery  # noqa: F401
    except ImportError as exc:
        pytest.fail(f"--docs needs the docs extra ({exc.name} is missing): "
                    "pip install -e '.[docs]'", pytrace=False)


def _chromium() -> str:
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    if path is None:
        pytest.fail("--docs needs Debian's Chromium for the browser check: "
                    "apt-get install -y chromium (sudo apt-get install -y chromium as a "
                    "non-root user)", pytrace=False)
    return path


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site built into a temporary directory; the build's output and times."""
    _require_sphinx()
    out = tmp_path_factory.mktemp("docs") / "html"
    env = {**os.environ, "DEBENCH_THREADS": "1", "MPLBACKEND": "Agg"}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    run = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-n", "-E",
                          "-b", "html", str(DOCS), str(out)],
                         capture_output=True, text=True, env=env, timeout=1800)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    print(f"\ndocs build: {wall:.1f} s wall, {cpu:.1f} s CPU")
    return {"out": out, "run": run, "wall": wall, "cpu": cpu}


def _pages(out: Path) -> list[Path]:
    return sorted(p for p in out.rglob("*.html") if "_static" not in p.parts)


def test_site_builds_with_no_warning(site):
    run = site["run"]
    log = run.stdout + run.stderr
    warnings = [line for line in log.splitlines() if "WARNING" in line or "ERROR" in line]
    assert run.returncode == 0 and not warnings, (
        f"sphinx-build exited {run.returncode} with {len(warnings)} warning(s):\n"
        + "\n".join(warnings[:40]) + f"\n--- end of the log:\n{log[-3000:]}")
    assert "build succeeded" in log


def _public_modules() -> list[str]:
    import pkgutil

    import debench.models as pkg

    names = ["debench.models"] + [m.name for m in pkgutil.walk_packages(
        pkg.__path__, prefix="debench.models.")]
    return sorted(n for n in names if not any(p.startswith("_") for p in n.split(".")))


def test_every_problem_dataset_module_and_public_function_has_a_page(site):
    from debench.reference import problems
    from debench.reference.datasets import data_dir, read_manifest

    out = site["out"]
    missing = [f"problem {p.id}" for p in problems.load_all()
               if not (out / "generated" / "problems" / f"{p.id}.html").is_file()]
    missing += [f"dataset {f}" for f in read_manifest(data_dir())
                if not (out / "generated" / "datasets" / f"{Path(f).stem}.html").is_file()]
    for mod in _public_modules() + ["debench.testing", "debench.pytest_plugin"]:
        page = out / "generated" / "api" / f"{mod}.html"
        if not page.is_file():
            missing.append(f"module {mod}")
            continue
        html = page.read_text()
        m = importlib.import_module(mod)
        for name, obj in vars(m).items():
            if name.startswith("_") or getattr(obj, "__module__", None) != mod:
                continue
            if (inspect.isfunction(obj) or inspect.isclass(obj)) and \
                    f'id="{mod}.{name}"' not in html:
                missing.append(f"{mod}.{name} (no entry on its module's page)")
    for page in ("index", "getting-started", "generated/verdict", "generated/errata",
                 "generated/cli", "generated/peers", "performance", "cite", "changelog",
                 "auto_examples/index", "auto_examples/free_membrane_nh"):
        if not (out / f"{page}.html").is_file():
            missing.append(f"page {page}")
    assert not missing, "no page for:\n" + "\n".join(missing)


class _Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.links: list[str] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(a["id"])
        if tag == "a" and a.get("name"):
            self.ids.add(a["name"])
        for key in ("href", "src"):
            if a.get(key) and not (tag == "link" and a.get("rel") == "preload"):
                self.links.append(a[key])


@functools.cache
def _parsed(path: Path) -> _Links:
    p = _Links()
    p.feed(path.read_text(errors="replace"))
    return p


def test_every_internal_link_and_anchor_resolves(site):
    out = site["out"]
    bad = []
    for page in _pages(out):
        for link in _parsed(page).links:
            parts = urlsplit(link)
            if parts.scheme or link.startswith(("//", "mailto:", "javascript:", "data:")):
                continue  # external: not checkable offline
            target = page if not parts.path else (page.parent / unquote(parts.path))
            target = target.resolve()
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                bad.append(f"{page.relative_to(out)}: {link} (no such file)")
            elif parts.fragment and target.suffix == ".html" and \
                    unquote(parts.fragment) not in _parsed(target).ids:
                bad.append(f"{page.relative_to(out)}: {link} (no such anchor)")
    assert not bad, f"{len(bad)} broken internal link(s):\n" + "\n".join(bad[:50])


_HARNESS_RUN = """    f.src = url;
    document.body.appendChild(f);
  });
}
(async () => {
  const out = [];
  for (const u of URLS) { out.push(await check(u)); }
  document.getElementById("result").textContent = "RESULT " + JSON.stringify(out);
})();
</script></body></html>"""
"""The end of both harness pages: each ``check(url)`` loads its iframe, and the results of
every URL, in order, are written into ``<pre id="result">``."""


def _harness(urls: list[str]) -> str:
    """A page that opens each URL in a same-origin iframe and writes, per page, its title,
    its first heading and the ``<img>`` that did not load into ``<pre id="result">``."""
    page = """<!doctype html><html><body><pre id="result">pending</pre><script>
const URLS = @URLS@;
function check(url) {
  return new Promise(resolve => {
    const f = document.createElement("iframe");
    f.style.width = "1200px"; f.style.height = "900px";
    f.onload = () => {
      const d = f.contentDocument;
      const imgs = Array.from(d.images);
      imgs.forEach(i => { i.loading = "eager"; });
      const t0 = Date.now();
      const wait = () => {
        if (imgs.every(i => i.complete) || Date.now() - t0 > 15000) {
          resolve({url: url, title: d.title,
                   h1: (d.querySelector("h1") || {textContent: ""}).textContent.trim(),
                   images: imgs.length,
                   broken: imgs.filter(i => !(i.complete && i.naturalWidth > 0))
                               .map(i => i.getAttribute("src"))});
        } else { setTimeout(wait, 50); }
      };
      wait();
    };
""" + _HARNESS_RUN
    return page.replace("@URLS@", json.dumps(urls))


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):  # the test reports what matters
        pass


def test_browser_renders_index_and_a_problem_page(site, tmp_path):
    chromium = _chromium()
    out = site["out"]
    assert (out / PROBLEM_PAGE).is_file(), PROBLEM_PAGE
    (out / "_browser_check.html").write_text(_harness(["index.html", PROBLEM_PAGE]))
    handler = functools.partial(_Quiet, directory=str(out))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        url = f"http://127.0.0.1:{server.server_address[1]}/_browser_check.html"
        run = subprocess.run([chromium, *CHROMIUM_FLAGS, f"--user-data-dir={tmp_path}",
                              f"--virtual-time-budget={BROWSER_BUDGET_MS}", "--dump-dom", url],
                             capture_output=True, text=True, timeout=180)
    finally:
        server.shutdown()
        server.server_close()
    m = re.search(r"RESULT (\[.*?\])</pre>", run.stdout, re.S)
    assert m, (f"chromium did not report (exit {run.returncode}):\n{run.stdout[-2000:]}\n"
               f"{run.stderr[-2000:]}")
    import html as _html

    index, problem = json.loads(_html.unescape(m[1]))
    assert "debench" in index["title"], index
    assert index["h1"].startswith("debench"), index
    assert "ch3_failure_points" in problem["title"], problem
    assert problem["images"] >= 1, problem
    for page in (index, problem):
        assert not page["broken"], f"{page['url']}: images not loaded: {page['broken']}"


def _layout_harness(urls: list[str], width: int) -> str:
    """A page that opens each URL in a same-origin iframe ``width`` px wide and writes, per
    page, the tables wider than the room they have (their scroll container or, without
    one, their parent, and the article column) and the Python reprs
    (:data:`RAW_REPRS`) in the article's text, into ``<pre id="result">``."""
    page = """<!doctype html><html><body><pre id="result">pending</pre><script>
const URLS = @URLS@, WIDTH = @WIDTH@, REPRS = @REPRS@;
function check(url) {
  return new Promise(resolve => {
    const f = document.createElement("iframe");
    f.style.width = WIDTH + "px"; f.style.height = "1000px";
    f.onload = () => {
      const d = f.contentDocument;
      const article = d.querySelector(".bd-article") || d.body;
      const room = article.getBoundingClientRect();
      const over = [];
      d.querySelectorAll("table").forEach((t, i) => {
        const box = t.closest(".pst-scrollable-table-container") || t.parentElement;
        const r = t.getBoundingClientRect();
        if (r.width === 0) { return; }
        if (r.width > box.clientWidth + 1 || r.right > room.right + 1 ||
            t.scrollWidth > t.clientWidth + 1) {
          const cell = t.querySelector("th") || t.querySelector("td");
          over.push({table: i, first_cell: cell ? cell.textContent.trim().slice(0, 40) : "",
                     width: Math.round(r.width), room: box.clientWidth});
        }
      });
      // the text a reader reads as data: code blocks and inline code are what authors
      // quote on purpose (the changelog names np.float64(...)); an API signature is
      // Python source, where {' is a dict literal (a numpy scalar is still a repr there)
      const readable = (drop) => {
        const c = article.cloneNode(true);
        c.querySelectorAll(drop).forEach(e => e.remove());
        return c.textContent;
      };
      const texts = {"np.float64(": readable("pre, code"),
                     "{'": readable("pre, code, .sig")};
      const reprs = [];
      for (const pat of REPRS) {
        const text = texts[pat] === undefined ? readable("pre, code") : texts[pat];
        let k = text.indexOf(pat);
        if (k >= 0) { reprs.push(text.slice(Math.max(0, k - 60), k + 60)); }
      }
      resolve({url: url, tables: d.querySelectorAll("table").length, overflow: over,
               reprs: reprs});
      f.remove();
    };
""" + _HARNESS_RUN
    return (page.replace("@URLS@", json.dumps(urls)).replace("@WIDTH@", str(width))
            .replace("@REPRS@", json.dumps(list(RAW_REPRS))))


def _reader_pages(out: Path) -> list[str]:
    """Every page a reader opens (not the search, index or source-listing pages)."""
    skip = {"search.html", "genindex.html", "py-modindex.html"}
    return [p.relative_to(out).as_posix() for p in _pages(out)
            if p.name not in skip and not p.name.startswith("_browser")
            and not set(p.relative_to(out).parts) & {"_sources", "_modules", "_downloads",
                                                     "_images"}]


def _browse(chromium: str, out: Path, harness: str, tmp_path: Path, budget_ms: int):
    """Serve ``out`` locally, open ``harness`` (written to ``out``) in headless Chromium
    and return the JSON it reports."""
    name = "_browser_layout.html"
    (out / name).write_text(harness)
    handler = functools.partial(_Quiet, directory=str(out))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        url = f"http://127.0.0.1:{server.server_address[1]}/{name}"
        run = subprocess.run([chromium, *CHROMIUM_FLAGS, f"--user-data-dir={tmp_path}",
                              f"--window-size={LAYOUT_WIDTH_PX + 200},1100",
                              f"--virtual-time-budget={budget_ms}", "--dump-dom", url],
                             capture_output=True, text=True, timeout=900)
    finally:
        server.shutdown()
        server.server_close()
    m = re.search(r"RESULT (\[.*?\])</pre>", run.stdout, re.S)
    assert m, (f"chromium did not report (exit {run.returncode}):\n{run.stdout[-2000:]}\n"
               f"{run.stderr[-2000:]}")
    import html as _html

    return json.loads(_html.unescape(m[1]))


def test_no_table_overflows_and_no_python_repr_at_1400_px(site, tmp_path):
    """Issue 48: at a 1400 px window no table of any page is wider than the room it has
    (docs/_static/custom.css lets cells wrap), and no page shows a Python repr in the text
    it gives as data (prose, tables, autodoc values; code a page quotes on purpose and
    dict literals of API signatures aside)."""
    chromium = _chromium()
    out = site["out"]
    urls = _reader_pages(out)
    assert "generated/errata.html" in urls and "generated/verdict.html" in urls
    pages = _browse(chromium, out, _layout_harness(urls, LAYOUT_WIDTH_PX), tmp_path,
                    LAYOUT_BUDGET_MS)
    assert [p["url"] for p in pages] == urls, "the browser did not lay out every page"
    assert sum(p["tables"] for p in pages) > 0
    over = [f"{p['url']}: {o}" for p in pages for o in p["overflow"]]
    reprs = [f"{p['url']}: ...{r}..." for p in pages for r in p["reprs"]]
    assert not over, f"{len(over)} table(s) overflow at {LAYOUT_WIDTH_PX} px:\n" + \
        "\n".join(over[:40])
    assert not reprs, "Python reprs on pages:\n" + "\n".join(reprs[:40])


def test_problem_pages_offer_reference_downloads_and_the_consensus_plot(site):
    """Every problem page links its JSON (the data ``debench problems ID --json`` prints)
    and a CSV per quantity, the files exist in the built site, the JSON is that data, and
    each problem with curated submissions shows its plot beside the other codes."""
    from debench.reference import consensus, problems
    from debench.reference.problems_reference import reference_json

    out = site["out"]
    with_peers = {t.problem for t in consensus.tables() if t.rows}
    missing = []
    for p in problems.load_all():
        page = (out / "generated" / "problems" / f"{p.id}.html")
        parsed = _parsed(page)
        files = {Path(unquote(link)).name: (page.parent / unquote(link)).resolve()
                 for link in parsed.links if "_downloads/" in link}
        wanted = [f"{p.id}.json"] + [f"{p.id}.{q.name}.csv" for q in p.quantities]
        missing += [f"{p.id}: {w}" for w in wanted if w not in files or
                    not files[w].is_file()]
        if f"{p.id}.json" in files and files[f"{p.id}.json"].is_file():
            shown = json.loads(files[f"{p.id}.json"].read_text())
            assert shown == json.loads(json.dumps(reference_json(p), ensure_ascii=False))
        if p.id in with_peers and not any(link.endswith(".consensus.png")
                                          for link in parsed.links):
            missing.append(f"{p.id}: the plot beside the other codes")
    assert not missing, "problem pages lack:\n" + "\n".join(missing)
