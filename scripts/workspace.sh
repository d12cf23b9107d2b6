# Sourced by the shell scripts: sets repo (this checkout) and ws (its catkin workspace).
# The workspace lives beside the checkout, outside the source tree, so that find and rosrun
# never walk into it from the package: <checkout>_ws, or $SURGICAL_SIM_WS when set. The checkout
# is taken with symlinks resolved (a script reached through <ws>/src/surgical_sim still finds
# <checkout>_ws). ccache (which scripts/setup installs) keys objects on paths relative to the
# checkout's parent, so another checkout of the same tree reuses them.
# --help or -h among the script's arguments prints its header comment (its usage) and exits 0
# before anything is installed, built or written.
for _ss_arg in "$@"; do
  case $_ss_arg in
  --help | -h)
    sed -n '2,/^[^#]/{/^#/s/^# \{0,1\}//p}' "$0"
    exit 0
    ;;
  esac
done
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)
ws=${SURGICAL_SIM_WS:-$(dirname "$repo")/$(basename "$repo")_ws}
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$(dirname "$repo")} CCACHE_NOHASHDIR=1
