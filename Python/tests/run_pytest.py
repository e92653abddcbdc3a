"""Runs the pytest suite of the Python package for ctest.

pytest is Debian's python3-pytest: installed here when absent and we are
root (apt-get), otherwise the suite reports a skip (exit 77), never a pass.
"""
import os
import subprocess
import sys

SKIP = 77
# The tools run here never get the sanitizers' runtimes the interpreter
# may have been started with.
TOOL_ENV = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}


def have_pytest():
    try:
        import pytest  # noqa: F401
        return True
    except ImportError:
        return False


def install_pytest():
    if os.geteuid() != 0:
        print("python3-pytest is not installed and we are not root: apt-get install python3-pytest")
        return False
    lock = ["-o", "DPkg::Lock::Timeout=600"]
    env = dict(TOOL_ENV, DEBIAN_FRONTEND="noninteractive")
    if subprocess.call(["apt-get", *lock, "install", "-y", "python3-pytest"], env=env) != 0:
        subprocess.call(["apt-get", *lock, "update"], env=env)
        if subprocess.call(["apt-get", *lock, "install", "-y", "python3-pytest"], env=env) != 0:
            print("apt-get could not install python3-pytest")
            return False
    import importlib
    importlib.invalidate_caches()
    return have_pytest()


def main():
    if not have_pytest() and not install_pytest():
        print("skipped: no pytest")
        return SKIP
    import pytest
    folder = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    return pytest.main(["-q", "-p", "no:cacheprovider", folder])


if __name__ == "__main__":
    sys.exit(main())
