"""Test classes that need something a Rust test sets up (an environment variable naming it).

Without it the class is skipped, saying so in unittest's report, except when the environment
variable ``CI`` is set: there every test must run, so the class fails instead (its
``setUpClass`` raises, which unittest reports as an error)."""

import os
import unittest
from typing import Callable, Type, TypeVar

T = TypeVar("T", bound=Type[unittest.TestCase])


def env(var: str, how: str) -> Callable[[T], T]:
    """Class decorator: run the class only with the environment variable ``var`` set;
    ``how`` says what sets it (e.g. the cargo test that does)."""

    def wrap(cls: T) -> T:
        if os.environ.get(var):
            return cls
        why = "%s is not set: %s" % (var, how)
        if not os.environ.get("CI"):
            return unittest.skip(why)(cls)

        def fail(_cls: type) -> None:
            raise AssertionError("%s; CI is set, where a skipped test is a failure" % why)

        cls.setUpClass = classmethod(fail)  # type: ignore[assignment]
        return cls

    return wrap
