"""The lcm-spy types jar: built when a JDK is present, its classes carry the same LCM
fingerprints as the Python types (so lcm-spy decodes what the daemon and the harness send)."""
from __future__ import annotations

import re
import shutil
import subprocess
import zipfile

import pytest

from f16mmae import lcmt_command_frame, lcmt_mmae_reset, lcmt_mmae_status, lcmt_sensor_frame
from f16mmae.lcm import spy

JDK = shutil.which("javac") and shutil.which("javap")
pytestmark = pytest.mark.skipif(not JDK, reason="no JDK here: the lcm-spy types jar is optional "
                                                "and built only with one (Debian default-jdk-headless)")

LINK_TYPES = (lcmt_sensor_frame, lcmt_command_frame, lcmt_mmae_reset, lcmt_mmae_status)


def _fingerprint(base: int) -> int:
    """LCM's fingerprint of a type with no nested LCM types: its base hash rotated left by 1."""
    rotated = ((base << 1) & 0xFFFFFFFFFFFFFFFF) | ((base >> 63) & 1)
    return rotated - (1 << 64) if rotated >= 1 << 63 else rotated


def test_the_jar_holds_every_message_type():
    names = set(zipfile.ZipFile(spy.types_jar()).namelist())
    for t in LINK_TYPES:
        assert f"f16mmae/{t.__name__}.class" in names


@pytest.mark.parametrize("msg", LINK_TYPES, ids=lambda t: t.__name__)
def test_java_and_python_fingerprints_agree(msg):
    out = subprocess.run(["javap", "-constants", "-cp", str(spy.types_jar()), f"f16mmae.{msg.__name__}"],
                         capture_output=True, text=True, check=True).stdout
    base = int(re.search(r"LCM_FINGERPRINT_BASE = (-?\d+)l;", out).group(1))
    python = int.from_bytes(msg._get_packed_fingerprint(), "big", signed=True)
    assert _fingerprint(base & 0xFFFFFFFFFFFFFFFF) == python


def test_classpath_puts_the_jar_first():
    cp = spy.classpath("/elsewhere/other.jar")
    assert cp.split(":") == [str(spy.types_jar()), "/elsewhere/other.jar"]
