#!/usr/bin/env bash
# Generate and build the ROS 2 interface packages that PyPI lacks (control_msgs, vendored in
# interfaces/) with the real rosidl generators and ament_cmake of the ROS 2 wheels, and install
# them into a virtual environment made from requirements.txt (Kilted) or jazzy/requirements.txt:
#
#   tests/ros2/build-interfaces.sh VENV SCRATCH [INTERFACES]
#
# VENV: the virtual environment (its python is CPython 3.11 with requirements.txt installed);
# it is also the install prefix, as the wheels make it one: libraries go to VENV/lib (which the
# wheels' bootstrap puts on LD_LIBRARY_PATH when its python starts), the ament index and CMake
# files to VENV/share, the Python package to its site-packages.
# SCRATCH: a directory for the build trees (emptied first, so a run starts from nothing).
# INTERFACES: the directory of the vendored packages, the distribution's: tests/ros2/interfaces
# (control_msgs 6.8.0, Kilted; the default) or tests/ros2/jazzy/interfaces (5.8.0, Jazzy).
#
# Needs cmake, make, a C and C++ compiler and Python's headers (Debian: cmake make g++
# python3-dev).
# Any failure stops the script with the failing tool's output and a non-zero status.
set -euo pipefail

if [ $# -ne 2 ] && [ $# -ne 3 ]; then
    echo "usage: $0 VENV SCRATCH [INTERFACES]" >&2
    exit 2
fi
venv=$(realpath "$1")
scratch=$2
here=$(cd "$(dirname "$0")" && pwd)
interfaces=$(realpath "${3:-$here/interfaces}")
py="$venv/bin/python"

fail() {
    echo "build-interfaces.sh: $*" >&2
    exit 1
}

[ -x "$py" ] || fail "$py is not an executable: VENV must be a virtual environment"
for tool in cmake make cc c++; do
    command -v "$tool" > /dev/null || fail "$tool is not on PATH (Debian: apt-get install cmake make g++)"
done
version=$("$py" -c 'import sys; print("%d.%d" % sys.version_info[:2])')
[ "$version" = 3.11 ] || fail "$py is Python $version: the ROS 2 wheels are for CPython 3.11"
py_include=$("$py" -c 'import sysconfig; print(sysconfig.get_paths()["include"])')
[ -f "$py_include/Python.h" ] \
    || fail "no Python.h in $py_include (Debian: apt-get install python3-dev)"
numpy_include=$("$py" -c 'import numpy; print(numpy.get_include())') \
    || fail "numpy cannot be imported by $py: install requirements.txt first"

mkdir -p "$scratch"
scratch=$(realpath "$scratch")

# One package now; more go here in dependency order.
for package in control_msgs; do
    build="$scratch/$package"
    rm -rf "$build"
    mkdir -p "$build"
    log="$build/build.log"
    echo "building $package in $build (log: $log)"
    # cmake's output goes to the log, and to stderr when a step fails.
    step() {
        if ! "$@" >> "$log" 2>&1; then
            cat "$log" >&2
            fail "$package: '$*' failed (its output is above)"
        fi
    }
    step cmake -S "$interfaces/$package" -B "$build" \
        -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_PREFIX_PATH="$venv" \
        -DCMAKE_INSTALL_PREFIX="$venv" \
        -DPython3_EXECUTABLE="$py" \
        -DBUILD_TESTING=OFF \
        -DCMAKE_PROJECT_INCLUDE="$here/wheel-include-dirs.cmake" \
        -DMCM_PYTHON_INCLUDE="$py_include" \
        -DMCM_NUMPY_INCLUDE="$numpy_include"
    step cmake --build "$build" --parallel "${CMAKE_BUILD_PARALLEL_LEVEL:-2}"
    step cmake --install "$build"
done

# The proof that the result is usable: the type support loads in the venv's rclpy.
"$py" -c '
from control_msgs.action import FollowJointTrajectory
from control_msgs.msg import JointTolerance
from rclpy.type_support import check_for_type_support
check_for_type_support(FollowJointTrajectory)
check_for_type_support(JointTolerance)
print("control_msgs type support loads:", FollowJointTrajectory.__module__)
' || fail "control_msgs was installed into $venv but its Python type support does not load"
