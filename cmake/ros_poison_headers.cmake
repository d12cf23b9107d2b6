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
