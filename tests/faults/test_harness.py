"""The fault suite's harness itself: a crash and a hang fail the case, a clean exit does not."""

from __future__ import annotations

import pytest

from faults.harness import dentopo, python


def test_a_clean_run_is_reported_with_its_exit_code_and_output():
    ran = dentopo("--version")
    assert ran.returncode == 0
    assert "dentopo" in ran.stdout


def test_a_crash_fails_the_case():
    with pytest.raises(pytest.fail.Exception, match="crashed with SIGSEGV"):
        python("import os, signal; os.kill(os.getpid(), signal.SIGSEGV)")


def test_a_hang_fails_the_case():
    with pytest.raises(pytest.fail.Exception, match="hung for more than"):
        python("import time; time.sleep(30)", timeout=1.0)
