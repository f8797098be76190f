"""The documentation runs as written: every fenced Python block of README.md and
docs/*.md, every shell command of the README (against the output it shows), and
docs/scenes.md's generated tables are those of the code.

A Python block runs statement by statement in a fresh namespace, in a scratch
directory that sees the repository's scenes/ and examples/ (so ``results/...``
lands there); an expression whose line ends in ``# -> VALUE`` must give VALUE
(its repr, ``...`` matching any rest, as in a doctest). A block that cannot run
says why in its info string, ```` ```python skip="reason" ````; one that runs
the FE model is marked ```` ```python slow ````.
"""

import ast
import doctest
import importlib.util
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT, child_environment

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^```python(?P<info>[^\n]*)\n(?P<code>.*?)^```", re.MULTILINE | re.DOTALL)
OPTION = re.compile(r'(\w+)(?:="([^"]*)")?')


def python_blocks():
    """(page, line, info options, code) of every fenced Python block."""
    for page in PAGES:
        text = page.read_text()
        for block in FENCE.finditer(text):
            line = text.count("\n", 0, block.start()) + 1
            options = {name: value for name, value in OPTION.findall(block["info"])}
            yield page, line, options, block["code"]


def _block_param(page, line, options, code):
    marks = [pytest.mark.slow] if "slow" in options else []
    return pytest.param(page, options, code, marks=marks,
                        id=f"{page.relative_to(ROOT).as_posix()}:{line}")


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    """A directory that sees the repository's scenes and examples, as the current one."""
    for name in ("scenes", "examples"):
        (tmp_path / name).symlink_to(ROOT / name)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def run_block(code: str, where: str) -> int:
    """Run ``code`` statement by statement; check every ``# -> VALUE``; the number checked."""
    lines = code.splitlines()
    namespace = {"__name__": "__docs__"}
    checked = 0
    checker = doctest.OutputChecker()
    for node in ast.parse(code).body:
        _, arrow, shown = lines[node.end_lineno - 1].partition("# ->")
        if isinstance(node, ast.Expr):
            value = eval(compile(ast.Expression(node.value), where, "eval"), namespace)
        else:
            exec(compile(ast.Module([node], []), where, "exec"), namespace)
        if arrow:
            assert isinstance(node, ast.Expr), f"{where}: '# ->' after a statement, not a value"
            got = repr(value)
            assert checker.check_output(shown.strip() + "\n", got + "\n", doctest.ELLIPSIS), \
                f"{where} line {node.lineno}: shows {shown.strip()}, gives {got}"
            checked += 1
    return checked


@pytest.mark.parametrize("page, options, code", [_block_param(*b) for b in python_blocks()])
def test_python_block_runs_as_written(scratch, page, options, code):
    where = page.relative_to(ROOT).as_posix()
    if "skip" in options:
        reason = options["skip"] or ""
        assert len(reason.split()) >= 3, f"{where}: a skipped block says why, in a few words"
        pytest.skip(reason)
    shown = code.count("# ->")
    assert run_block(code, where) == shown


def test_every_python_block_runs_or_says_why_not():
    """A block is run, or skipped with its reason; a block that includes a file (a snippet)
    names one that exists."""
    blocks = list(python_blocks())
    assert len(blocks) >= 10
    for page, line, options, code in blocks:
        snippet = re.fullmatch(r'--8<-- "([^"]+)"\n', code)
        if snippet:
            assert (ROOT / snippet[1]).is_file(), f"{page.name}:{line}: {snippet[1]}"
            assert options.get("skip"), f"{page.name}:{line}: a whole file: say where it runs"


# The README's shell commands: the command as the test runs it, and its marks; or the
# reason it is not run here. A command added to the README fails until it is listed.
VIBROFRIC = ".venv/bin/vibrofric"
NOT_RUN = {
    "make test": "the test suite itself",
    "make figures": "tests/test_examples.py runs every figure script in its fast form",
    "make docs": "needs MkDocs (the docs extra), which the test environment does not install",
    "VIBROFRIC_LAW=my_law.py .venv/bin/python -m pytest tests/test_law_contract.py -k my_law":
        "my_law.py is the reader's own law; test_law_contract.py's "
        "test_a_users_law_is_selected_by_its_file_name runs the command on a law file",
}
FAST = {"analytic", "keys"}          # the other commands run the FE model or a sweep


def readme_commands() -> list:
    """Every shell command of the README's indented blocks (continuations joined,
    comments and a leading ``$`` dropped), in order."""
    commands, text = [], (ROOT / "README.md").read_text()
    joined = re.sub(r"\\\n\s+", "", text)
    for line in joined.splitlines():
        if not line.startswith("    ") or line.startswith("     "):
            continue
        line = line[4:].removeprefix("$ ")
        if line.startswith(("make ", ".venv/", "VIBROFRIC_LAW=")):
            commands.append(re.split(r"\s{2,}#", line)[0].strip())
    return commands


def stated_output(command: str) -> str:
    """The line the README shows under ``$ command``."""
    lines = (ROOT / "README.md").read_text().splitlines()
    return lines[lines.index(f"    $ {command}") + 1].strip()


def demo_command() -> list:
    """make demo's recipe (Makefile), as this test runs it."""
    makefile = (ROOT / "Makefile").read_text()
    recipe = re.search(r"^demo:.*\n\t(.+)$", makefile, re.MULTILINE)[1]
    recipe = recipe.replace("$(VENV)/bin/vibrofric", VIBROFRIC).replace("$(DEMO_OUT)",
                                                                         "results/demo")
    return shlex.split(recipe)


def run_command(words: list, cwd: Path) -> subprocess.CompletedProcess:
    if words[0] == VIBROFRIC:
        words = [sys.executable, "-m", "vibrofric.cli", *words[1:]]
    done = subprocess.run(words, cwd=cwd, capture_output=True, text=True, timeout=1200,
                          env=child_environment(MPLBACKEND="Agg"))
    assert done.returncode == 0, f"{' '.join(words)}: {done.stderr[-2000:]}"
    return done


NUMBER = re.compile(r"-?\d+(?:\.\d+)?")
WALL_TIME = re.compile(r"\d+(?:\.\d+)? s([;)])")   # a run's seconds: this machine's


def same_within_stated_digits(stated: str, said: str) -> None:
    """The same line, each number within half a unit of the stated one's last digit
    (a run's wall time, which is the machine's, left out)."""
    stated, said = WALL_TIME.sub(r"<t> s\1", stated), WALL_TIME.sub(r"<t> s\1", said)
    assert NUMBER.sub("#", stated) == NUMBER.sub("#", said), (stated, said)
    for shown, got in zip(NUMBER.findall(stated), NUMBER.findall(said)):
        digits = len(shown.partition(".")[2])
        assert abs(float(got) - float(shown)) <= 0.5 * 10.0 ** -digits + 1e-12, (shown, got)


def _command_param(command):
    marks = [pytest.mark.slow] if shlex.split(command)[1] not in FAST else []
    return pytest.param(command, marks=marks, id=command[:60])


RUN = [command for command in readme_commands() if command not in NOT_RUN
       and command.startswith(VIBROFRIC)]


def test_every_readme_command_is_run_or_says_why_not():
    commands = readme_commands()
    assert "make demo" in commands and len(RUN) >= 7
    for command in commands:
        assert command in NOT_RUN or command in RUN or command == "make demo", command


@pytest.mark.parametrize("command", [_command_param(c) for c in RUN])
def test_readme_command_runs(scratch, command):
    """Each command as written (from a directory of its own), and what it says it writes."""
    words = shlex.split(command)
    done = run_command(words, scratch)
    if "--out" in words:
        out = scratch / words[words.index("--out") + 1]
        assert {"scene.toml", "summary.json"} <= {p.name for p in out.iterdir()}
    elif words[1] in ("analytic", "run", "sweep"):    # the default results directory
        assert len(list((scratch / "results").iterdir())) == 1
    if words[1] == "keys":
        assert done.stdout.splitlines()[0].split() == ["key", "value", "default", "unit",
                                                       "meaning"]


@pytest.mark.slow
def test_make_demo_gives_what_the_readme_shows(scratch):
    """make demo's recipe: its line as the README shows it (numbers within their digits),
    the files the README lists, and the README's prose numbers of it."""
    import json

    done = run_command(demo_command(), scratch)
    same_within_stated_digits(stated_output("make demo"), done.stdout.strip())
    demo = scratch / "results" / "demo"
    names = {p.name for p in demo.iterdir()}
    assert {"scene.toml", "summary.json", "timeseries.csv", "analytic_timeseries.csv",
            "paraview"} <= names and any(name.endswith(".png") for name in names)
    assert (demo / "paraview" / "block.pvd").is_file()
    summary = json.loads((demo / "summary.json").read_text())
    readme = (ROOT / "README.md").read_text()
    below = float(re.search(r"The FE block lies (\d+\.\d)% below the lumped body", readme)[1])
    assert abs(100 * summary["rel_error"] - below) <= 0.05
    fe, analytic = re.search(r"`make demo`: FE (\S+) and analytic\s+(\S+) where", readme).groups()
    assert abs(summary["fe"]["F_dv_over_F_d0"] - float(fe)) <= 5e-5
    assert abs(summary["analytic"]["F_dv_over_F_d0"] - float(analytic)) <= 5e-5


def test_scene_reference_is_current():
    """docs/scenes.md's tables are those docs/tools/scene_reference.py makes of the code
    (run it after changing a key)."""
    path = ROOT / "docs" / "tools" / "scene_reference.py"
    spec = importlib.util.spec_from_file_location("scene_reference", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    page = module.PAGE.read_text()
    assert module.page_with_reference(page) == page, \
        "docs/scenes.md is stale: run python docs/tools/scene_reference.py"
    assert "| `time.T` | float |" in page and "| `contact.dahl_exponent` |" in page
