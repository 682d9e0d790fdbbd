"""The transport theory and measurements in one module (alias for a release)."""; from .theory.transport import *; from .analysis.transport import *  # noqa: E702,F401,F403  alias for a release
