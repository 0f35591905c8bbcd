# coopdyn_find_mujoco(): look for Debian's MuJoCo (libmujoco-dev 2.2.2; CMake package `mujoco`,
# imported target mujoco::mujoco, headers <mujoco/mujoco.h>) for the dual-arm box example and its
# tests, in the calling directory's scope. MuJoCo is optional: COOPDYN_HAVE_MUJOCO says whether it
# was found, and the callers skip what needs it (with a message). -DCMAKE_DISABLE_FIND_PACKAGE_mujoco=ON
# configures as if it were missing.
#
# Debian's package lists /usr/include/libqhull_r/ in mujoco::mujoco's include directories without
# depending on libqhull-dev (MuJoCo's public headers do not need it), and CMake refuses a missing
# directory there: only the directories that exist are kept.
macro(coopdyn_find_mujoco)
  find_package(mujoco QUIET)
  if(mujoco_FOUND AND TARGET mujoco::mujoco)
    set(COOPDYN_HAVE_MUJOCO TRUE)
    get_target_property(_coopdyn_mujoco_includes mujoco::mujoco INTERFACE_INCLUDE_DIRECTORIES)
    set(_coopdyn_mujoco_existing_includes)
    foreach(_coopdyn_dir IN LISTS _coopdyn_mujoco_includes)
      if(EXISTS "${_coopdyn_dir}")
        list(APPEND _coopdyn_mujoco_existing_includes "${_coopdyn_dir}")
      endif()
    endforeach()
    set_target_properties(mujoco::mujoco PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${_coopdyn_mujoco_existing_includes}")
  else()
    set(COOPDYN_HAVE_MUJOCO FALSE)
  endif()
endmacro()
