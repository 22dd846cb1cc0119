"""``axmpm verify [--case NAME ...]``: the verification cases (closed-form references) through the
generic driver (:mod:`axmpm.cases.driver`). Default: the cases with ``default = True``
(today ``column_1d``, the large-deformation column)."""

from __future__ import annotations

import argparse
from typing import Any

from . import driver

NAME = "verify"
KIND = "verification"


def add_parser(sub: Any) -> argparse.ArgumentParser:
    return driver.add_parser(sub, KIND)


def main(args: argparse.Namespace) -> int:
    return driver.main(args, KIND)
