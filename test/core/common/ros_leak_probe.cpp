// Compile-only probe: the ROS-free core must reject ROS headers. Building this file with the core's
// include paths must FAIL; the tests "core_rejects_ros" (ctest) and rostest target core_boundary
// check that it does.
#include <ros/ros.h>
