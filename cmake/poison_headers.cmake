# "Poison" include directories: a directory of #error stubs searched before the real headers, so
# that an include crossing a boundary of the package fails to compile, naming the boundary.

# surgical_sim_ros_poison_dir(DIR): fills DIR with an #error stub for every header of the ROS
# packages installed under /usr/include (where Debian puts them). Searched before /usr/include by
# the core targets, it makes any <ros/...>-style include under the ROS-free core fail to compile.
function(surgical_sim_ros_poison_dir dir)
  foreach(pkg ros rosbag tf2_ros tf2_msgs std_msgs std_srvs geometry_msgs sensor_msgs
          visualization_msgs rosconsole roscpp)
    file(GLOB_RECURSE pkg_headers RELATIVE /usr/include /usr/include/${pkg}/*.h)
    foreach(h ${pkg_headers})
      if(NOT EXISTS ${dir}/${h})
        file(WRITE ${dir}/${h}
             "#error \"${h} included from the ROS-free surgical_sim core (src/core, include/surgical_sim/core)\"\n")
      endif()
    endforeach()
  endforeach()
  file(MAKE_DIRECTORY ${dir}/ros)
  file(WRITE ${dir}/ros/ros.h "#error \"ros/ros.h included from the ROS-free surgical_sim core\"\n")
endfunction()

# surgical_sim_bench_poison_dir(DIR INCLUDE_DIR): fills DIR with an #error stub for every header
# of the bench library (INCLUDE_DIR/surgical_sim/bench/*.h). Searched before INCLUDE_DIR by the
# core targets, it makes any "surgical_sim/bench/..." include under the core fail to compile: the
# bench library builds on the core, never the other way round.
function(surgical_sim_bench_poison_dir dir include_dir)
  file(GLOB bench_headers RELATIVE ${include_dir} ${include_dir}/surgical_sim/bench/*.h)
  foreach(h ${bench_headers})
    file(WRITE ${dir}/${h}
         "#error \"${h} included from the surgical_sim core: the core must not depend on the bench library\"\n")
  endforeach()
endfunction()
