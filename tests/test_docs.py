"""The documentation states what the code accepts: every ```toml block of the README is a valid
scenario, the tutorial's scenario passes ``axmpm check``, and the README names no key the schema
lacks."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

from axmpm.cli import main
from axmpm.errors import ScenarioError
from axmpm.scenario import Scenario

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
TUTORIAL = ROOT / "examples" / "footing_tutorial.toml"


def fenced_blocks(text: str, language: str) -> list[str]:
    """The bodies of the fenced code blocks of ``language`` in a markdown text, in order."""
    return re.findall(rf"^```{language}[ \t]*\n(.*?)^```[ \t]*$", text, flags=re.MULTILINE | re.DOTALL)


def test_fenced_blocks_are_found_and_a_bad_block_is_refused() -> None:
    text = "intro\n```toml\na = 1\n```\n\n```python\nx = 1\n```\n```toml\n[grid]\n```\n"
    assert fenced_blocks(text, "toml") == ["a = 1\n", "[grid]\n"]
    with pytest.raises(ScenarioError):
        Scenario.from_dict(tomllib.loads("[simulation]\nend_time = -1.0\n"))


README_TOML = fenced_blocks(README.read_text(encoding="utf-8"), "toml")
#: The scenario examples of the reference docs (toml blocks with a [simulation] table).
DOCS_SCENARIOS = [(path.relative_to(ROOT).as_posix(), block)
                  for path in sorted((ROOT / "docs").rglob("*.md"))
                  for block in fenced_blocks(path.read_text(encoding="utf-8"), "toml") if "[simulation]" in block]


def test_the_readme_has_a_scenario_per_problem_type() -> None:
    assert len(README_TOML) >= 2


@pytest.mark.parametrize("index", range(len(README_TOML)))
def test_every_readme_toml_block_is_a_valid_scenario(index: int) -> None:
    Scenario.from_dict(tomllib.loads(README_TOML[index]), source=f"README.md toml block {index}")


@pytest.mark.parametrize("source, block", DOCS_SCENARIOS, ids=[f"{p}:{i}" for i, (p, _) in enumerate(DOCS_SCENARIOS)])
def test_every_scenario_example_of_the_docs_is_valid(source: str, block: str) -> None:
    Scenario.from_dict(tomllib.loads(block), source=source)


def test_the_tutorial_scenario_passes_axmpm_check(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(TUTORIAL), "--no-estimate"]) == 0
    assert "is valid" in capsys.readouterr().out


def test_the_readme_tutorial_block_is_the_tutorial_file() -> None:
    """The README's excerpt of the tutorial gives the same scenario as the committed file, once
    the file's defaults are filled in (the excerpt leaves out names, origin and particles per
    cell, which are the defaults)."""
    excerpt = Scenario.from_dict(tomllib.loads(README_TOML[0]))
    full = Scenario.from_toml(TUTORIAL)
    ignore = {"name"}

    def strip(value: object) -> object:
        if isinstance(value, dict):
            return {k: strip(v) for k, v in value.items() if k not in ignore}
        if isinstance(value, list):
            return [strip(v) for v in value]
        return value

    assert strip(tomllib.loads(excerpt.to_toml())) == strip(tomllib.loads(full.to_toml()))


def test_docs_scenario_md_is_generated_from_the_schema() -> None:
    """docs/scenario.md documents every key of the schema: it is the output of
    docs/scenario_reference.py (regenerate with `python docs/scenario_reference.py > docs/scenario.md`)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("scenario_reference", ROOT / "docs" / "scenario_reference.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    expected = module.reference()
    assert "`stop_when_settled`" in expected and 'model = "mohr_coulomb"' in expected
    assert (ROOT / "docs" / "scenario.md").read_text(encoding="utf-8") == expected, \
        "docs/scenario.md is stale: run `python docs/scenario_reference.py > docs/scenario.md`"


def test_the_readme_stays_a_first_screen() -> None:
    """The README is for a user starting out (at most 250 lines); benchmarks, development and
    studies live in docs/ and CONTRIBUTING.md."""
    assert len(README.read_text(encoding="utf-8").splitlines()) <= 250


# --------------------------------------------------------------------------- references resolve

TEXT_SUFFIXES = (".md", ".py", ".rs", ".toml")
#: Files outside the repository that text used to cite; a clone has none of them.
OUTSIDE = ("PHYSICS" + ".md", "INTERFACES" + ".md", "../" + "shared")
#: History may name what it removed.
HISTORY = {"CHANGELOG.md"}
LINK = re.compile(r"\[[^\]\n]*\]\(([^)\s]+)\)")


def tracked_files() -> list[str]:
    """The repository's files: git's list, or a walk of the tree when this is not a checkout."""
    import subprocess

    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
        return [name for name in out.decode().split("\0") if name]
    except (OSError, subprocess.CalledProcessError):
        skip = {".git", ".venv", "target", "runs", ".pytest_cache"}
        return [p.relative_to(ROOT).as_posix() for p in ROOT.rglob("*")
                if p.is_file() and not skip.intersection(p.relative_to(ROOT).parts)]


def dangling_links(text: str, source: str, files: set[str], anchors=None) -> list[str]:
    """The relative markdown links of ``text`` (a file at ``source``) that name no file or folder
    of ``files``, or (with ``anchors``, a function of a markdown file's path giving its heading
    anchors) a heading that file does not have."""
    folders = {str(Path(f).parent.as_posix()) for f in files} | {
        p.as_posix() for f in files for p in Path(f).parents}
    bad = []
    for target in LINK.findall(text):
        if target.startswith(("http://", "https://", "mailto:", "#")):
            continue
        path = target.split("#", 1)[0]
        resolved = (Path(source).parent / path).as_posix()
        normal = Path(*[]) if not resolved else Path(resolved)
        parts: list[str] = []
        for part in normal.parts:
            if part == "..":
                if not parts:
                    parts.append("..")  # above the repository
                    break
                parts.pop()
            elif part != ".":
                parts.append(part)
        name = "/".join(parts).rstrip("/")
        if name not in files and name not in folders:
            bad.append(f"{source}: [..]({target})")
        elif "#" in target and name.endswith(".md") and anchors is not None:
            if target.split("#", 1)[1] not in anchors(name):
                bad.append(f"{source}: [..]({target}) (no such heading)")
    return bad


def heading_anchors(text: str) -> set[str]:
    """The anchors GitHub gives a markdown text's headings: lower case, punctuation dropped
    (letters, digits, spaces, hyphens and underscores kept), spaces as hyphens; repeats get -1,
    -2, ..."""
    anchors: set[str] = set()
    inside_code = False
    for line in text.splitlines():
        if line.startswith("```"):
            inside_code = not inside_code
        if inside_code or not re.match(r"#{1,6} ", line):
            continue
        slug = re.sub(r"[^\w\- ]", "", line.lstrip("#").strip().lower()).replace(" ", "-")
        candidate, n = slug, 0
        while candidate in anchors:
            n += 1
            candidate = f"{slug}-{n}"
        anchors.add(candidate)
    return anchors


def test_dangling_links_are_found() -> None:
    files = {"README.md", "docs/physics.md", "docs/studies/notes.md"}
    text = "[a](docs/physics.md#1-the-method) [b](docs/missing.md) [c](https://x.org/y.md) [d](docs/studies/)" \
           " [e](#limitations) [f](../outside.md)"
    assert dangling_links(text, "README.md", files) == ["README.md: [..](docs/missing.md)",
                                                        "README.md: [..](../outside.md)"]
    assert dangling_links("[p](../physics.md) [q](physics.md)", "docs/studies/notes.md", files) == [
        "docs/studies/notes.md: [..](physics.md)"]
    heads = {"docs/physics.md": heading_anchors("# Title\n## 8. Soil–structure: rigid bodies\n```\n# not\n```\n## 8. Soil–structure: rigid bodies\n")}
    assert heads["docs/physics.md"] == {"title", "8-soilstructure-rigid-bodies", "8-soilstructure-rigid-bodies-1"}
    text = "[a](docs/physics.md#8-soilstructure-rigid-bodies) [b](docs/physics.md#9-gone)"
    assert dangling_links(text, "README.md", files, heads.get) == [
        "README.md: [..](docs/physics.md#9-gone) (no such heading)"]


def test_no_text_file_refers_to_a_file_outside_the_repository() -> None:
    files = set(tracked_files())
    this = Path(__file__).resolve().relative_to(ROOT).as_posix()
    problems = []

    def anchors(name: str) -> set[str]:
        return heading_anchors((ROOT / name).read_text(encoding="utf-8"))

    for name in sorted(files):
        if not name.endswith(TEXT_SUFFIXES) or name == this or not (ROOT / name).is_file():
            continue
        text = (ROOT / name).read_text(encoding="utf-8", errors="replace")
        if name not in HISTORY:
            problems += [f"{name}: cites {outside}" for outside in OUTSIDE if outside in text]
        if name.endswith(".md"):
            problems += dangling_links(text, name, files, anchors)
    assert not problems, "references to files not in the repository:\n" + "\n".join(problems)


def test_the_readme_plot_runs_on_a_tutorial_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The README's Python plot reads a run of the tutorial's scenario (here a short, coarse one)
    and writes its figure."""
    from axmpm import run

    (python,) = fenced_blocks(README.read_text(encoding="utf-8"), "python")
    scenario = Scenario.from_toml(TUTORIAL, ["grid.cell_size=0.1", "simulation.end_time=0.1",
                                             "simulation.output_interval=0.05"])
    monkeypatch.chdir(tmp_path)
    run(scenario, tmp_path / "runs" / "footing", threads=1)
    exec(compile(python, "README.md", "exec"), {})
    assert (tmp_path / "runs" / "footing" / "load_settlement.png").stat().st_size > 0
