#!/bin/sh
# Debian's Python 3 without its site-packages: `import matplotlib` fails as it
# does where python3-matplotlib is not installed (PBF_PYTHON points here in
# the tests of that path).
exec /usr/bin/python3 -S "$@"
