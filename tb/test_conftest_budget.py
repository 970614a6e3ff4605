"""The suite's time budgets (tb/conftest.py) fail a test over its budget
and stop one that hangs: run on small inner sessions with the real
conftest."""
from pathlib import Path

pytest_plugins = ["pytester"]

CONFTEST = (Path(__file__).resolve().parent / "conftest.py").read_text()


def test_over_budget_fails(pytester):
    pytester.makeconftest(CONFTEST)
    pytester.makepyfile("""
        import pytest

        @pytest.mark.budget(0)
        def test_over():
            pass              # any duration is over a budget of 0 s

        @pytest.mark.budget(600)
        def test_within():
            pass
    """)
    res = pytester.runpytest_subprocess()
    res.assert_outcomes(passed=1, failed=1)
    res.stdout.fnmatch_lines(["*test_over passed but took * over its budget of 0 s*"])


def test_hang_is_stopped(pytester):
    pytester.makeconftest(CONFTEST)
    pytester.makepyfile("""
        import time
        import pytest

        @pytest.mark.budget(0.5)
        def test_hangs():
            time.sleep(60)    # stopped at HANG_FACTOR x 0.5 s, rounded up to 1 s
    """)
    res = pytester.runpytest_subprocess()
    res.assert_outcomes(failed=1)
    res.stdout.fnmatch_lines(["*stopped: still running at its hang limit*"])
