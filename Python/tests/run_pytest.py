"""Runs the pytest suite of the Python package for ctest.

pytest is Debian's python3-pytest: installed here when absent and we are
root (apt-get), otherwise the suite reports a skip (exit 77), never a pass.
"""
import os
import subprocess
import sys

SKIP = 77


def have_pytest():
    return subprocess.call([sys.executable, "-c", "import pytest"], stderr=subprocess.DEVNULL) == 0


def install_pytest():
    if os.geteuid() != 0:
        print("python3-pytest is not installed and we are not root: apt-get install python3-pytest")
        return False
    lock = ["-o", "DPkg::Lock::Timeout=600"]
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    if subprocess.call(["apt-get", *lock, "install", "-y", "python3-pytest"], env=env) != 0:
        subprocess.call(["apt-get", *lock, "update"], env=env)
        if subprocess.call(["apt-get", *lock, "install", "-y", "python3-pytest"], env=env) != 0:
            print("apt-get could not install python3-pytest")
            return False
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
