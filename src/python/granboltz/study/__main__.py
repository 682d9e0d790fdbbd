"""python -m granboltz.study run|table STUDY.yaml ...: the command line of granboltz.study.command."""
import sys

from .command import main

if __name__ == "__main__":  # not when a tool walks the package and imports every module
    sys.exit(main())
