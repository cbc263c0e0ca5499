"""Run fuzz cases: make each on disk, run every command, classify, clean up."""

from __future__ import annotations

import shutil
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

from support.fuzz.cases import COMMANDS, Case, commands, materialize, snapshot
from support.fuzz.classify import DEFECTS, Outcome, classify
from support.fuzz.runner import Runner


@dataclass(frozen=True)
class CaseResult:
    case: Case
    outcomes: tuple[Outcome, ...]

    @property
    def defects(self) -> list[Outcome]:
        return [o for o in self.outcomes if o.cls in DEFECTS]

    @property
    def unknown_defects(self) -> list[Outcome]:
        """Defects not reproduced by a strict xfail of code being rewritten."""
        return [o for o in self.defects if not o.known]


def run_case(runner: Runner, case: Case, work: Path, keep: bool = False,
             only: Iterable[str] = COMMANDS) -> CaseResult:
    """Every command of :data:`COMMANDS` (or ``only``) on ``case``, under ``work``."""
    folder = work / f"case{case.index}"
    if folder.exists():
        shutil.rmtree(folder)
    made = materialize(case, folder)
    argvs = commands(made)
    xml = case.group == "mesh" or case.fmt != "usd"
    outcomes = []
    for name in only:
        argv = argvs[name]
        before = snapshot(made.folder)
        run = runner.run(argv, folder, name)
        after = snapshot(made.folder)
        output = None if name == "check" else made.out / f"{name}{made.output_suffix}"
        inspected = None
        if output is not None and output.is_file() and not run.timed_out:
            inspected = runner.inspect(output, folder / f"{name}.inspect.json")
        outcomes.append(classify(name, run, before=before, after=after, out_dir=made.out,
                                 output=output, inspected=inspected, xml=xml))
    if not keep:
        shutil.rmtree(folder, ignore_errors=True)
    return CaseResult(case, tuple(outcomes))


def run_cases(runner: Runner, cases: Iterable[Case], work: Path, keep: bool = False,
              progress: Callable[[CaseResult], None] | None = None) -> list[CaseResult]:
    results = []
    for case in cases:
        result = run_case(runner, case, work, keep=keep)
        results.append(result)
        if progress is not None:
            progress(result)
    return results
