# Sourced by the job scripts: the Python of the tools is $LEM_PYTHON, else
# Debian's /usr/bin/python3 on Debian (its packages hold matplotlib, h5py
# and PyYAML; another python3 on PATH may not), else python3 from PATH.
if [ -z "${LEM_PYTHON:-}" ]; then
  LEM_PYTHON=python3
  [ -f /etc/debian_version ] && [ -x /usr/bin/python3 ] && LEM_PYTHON=/usr/bin/python3
fi
command -v "$LEM_PYTHON" > /dev/null || {
  echo "$(basename "$0"): LEM_PYTHON=$LEM_PYTHON is not a program: set LEM_PYTHON to a Python 3 with PyYAML, NumPy, SciPy, h5py and matplotlib" >&2
  exit 1
}
export LEM_PYTHON
