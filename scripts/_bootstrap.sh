# Sourced by scripts/demo and scripts/test: system packages and the project's virtual environment.
# Works on a fresh Debian with Python 3.11 and pip; installs what is missing, nothing more.

apt_install() {
    local missing=() package
    for package in "$@"; do
        dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    if ! command -v apt-get >/dev/null 2>&1; then
        echo "Engram needs the system packages: ${missing[*]}; install them and run again." >&2
        return 1
    fi
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo="sudo"
    echo "Installing system packages: ${missing[*]}"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

find_python() {
    local candidate
    for candidate in python3.11 python3 python; do
        if command -v "$candidate" >/dev/null 2>&1 &&
            "$candidate" -c 'import sys; sys.exit(sys.version_info < (3, 11))' 2>/dev/null; then
            echo "$candidate"
            return 0
        fi
    done
    echo "Engram needs Python 3.11 or newer on the PATH." >&2
    return 1
}

# Shared libraries that open3d's Python module links against (shapes/ uses it headless).
OPEN3D_LIBS=(libusb-1.0-0 libgl1 libegl1 libx11-6 libudev1 libgomp1)

# ensure_venv EXTRAS: create .venv if needed and install the project with those extras.
ensure_venv() {
    local python
    apt_install "${OPEN3D_LIBS[@]}" || return 1
    python=$(find_python) || return 1
    if [ ! -x .venv/bin/python ]; then
        if ! "$python" -m venv .venv 2>/dev/null; then
            rm -rf .venv
            apt_install python3-venv
            "$python" -m venv .venv
        fi
    fi
    .venv/bin/python -m pip install --quiet --disable-pip-version-check --upgrade pip
    .venv/bin/python -m pip install --quiet --disable-pip-version-check -e ".$1"
}
