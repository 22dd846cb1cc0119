"""``axmpm validate [--case NAME ...]``: the validation cases (experiments, empirical laws)
through the generic driver (:mod:`axmpm.cases.driver`). Default: the cases with
``default = True`` (today ``column_collapse``, the granular column collapses)."""

from __future__ import annotations

import argparse
from typing import Any

from . import driver

NAME = "validate"
KIND = "validation"


def add_parser(sub: Any) -> argparse.ArgumentParser:
    return driver.add_parser(sub, KIND)


def main(args: argparse.Namespace) -> int:
    return driver.main(args, KIND)
