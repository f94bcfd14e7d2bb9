"""lcm-spy with the project's message types: ``python -m f16mmae.lcm.spy [LCM-SPY ARGS]``.

lcm-spy (LCM's Java traffic viewer, shipped in the ``lcm`` wheel) decodes a channel when a
class of the message's type is on its CLASSPATH. The build compiles our ``lcm_types/*.lcm``
into ``f16mmae/java/f16mmae_lcmtypes.jar`` when a JDK is present (cmake/lcm_java.cmake); this
module puts that jar on CLASSPATH and starts lcm-spy, passing on its arguments
(e.g. ``--lcm-url udpm://239.255.76.67:7667?ttl=0``)."""
from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

from .. import core
from ..errors import F16mmaeError

JAR_NAME = "f16mmae_lcmtypes.jar"


class SpyError(F16mmaeError):
    """lcm-spy or the jar of our types is missing: the message says how to get it."""


def types_jar() -> Path:
    """The jar of the project's LCM types built beside ``f16mmae.core``; SpyError naming the
    fix when this build has none (it was built without a JDK)."""
    jar = Path(core.__file__).resolve().parent / "java" / JAR_NAME
    if not jar.is_file():
        raise SpyError(f"this build of f16mmae has no {JAR_NAME} (looked for {jar}): it is built when "
                       "a JDK is present; install one (Debian: default-jdk-headless) and rebuild "
                       "(make build)")
    return jar


def classpath(existing: str | None = None) -> str:
    """CLASSPATH with the types jar first, then ``existing`` (default: the environment's)."""
    existing = os.environ.get("CLASSPATH", "") if existing is None else existing
    return os.pathsep.join(p for p in (str(types_jar()), existing) if p)


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if args[:1] in (["-h"], ["--help"]):
        print(__doc__)
        return 0
    try:
        spy = shutil.which("lcm-spy") or shutil.which("lcm-spy", path=str(Path(sys.executable).parent))
        if spy is None:
            raise SpyError("lcm-spy is not on PATH: it comes with the lcm wheel (pip install lcm)")
        env = dict(os.environ, CLASSPATH=classpath())
    except SpyError as exc:
        print(f"f16mmae.lcm.spy: {exc}", file=sys.stderr)
        return 1
    os.execve(spy, [spy, *args], env)
    return 0  # not reached


if __name__ == "__main__":
    raise SystemExit(main())
