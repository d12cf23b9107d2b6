# Sourced by the shell scripts: sets repo (this checkout) and ws (its catkin workspace).
# The workspace lives beside the checkout, outside the source tree, so that find and rosrun
# never walk into it from the package: <checkout>_ws, or $SURGICAL_SIM_WS when set.
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
ws=${SURGICAL_SIM_WS:-$(dirname "$repo")/$(basename "$repo")_ws}
