# coopdyn_find_kdl(): look for Orocos KDL (Debian: liborocos-kdl-dev, CMake package orocos_kdl, which
# defines variables, not targets) and ROS's kdl_parser (Debian: libkdl-parser-dev), for the KDL
# adapter (include/coopdyn/adapters/kdl.hpp, kdl_urdf.hpp) and its tests and benchmark. Sets
# COOPDYN_HAVE_KDL, COOPDYN_KDL_LIBRARIES, COOPDYN_HAVE_KDL_PARSER, COOPDYN_KDL_PARSER_LIBRARIES.
#
# kdl_parser is found by its header and library, not by find_package(kdl_parser): Debian's
# kdl_parserConfig.cmake pulls in urdf, pluginlib and ament_cmake, which run Python modules
# (ament_package) that a non-ROS machine lacks, and its kdl_parser.pc requires a pluginlib.pc that
# no package installs. The library itself links on its own (its dependencies are in its ELF
# header). -DCMAKE_DISABLE_FIND_PACKAGE_orocos_kdl=ON configures as if KDL were missing,
# -DCOOPDYN_WITH_KDL_PARSER=OFF as if kdl_parser were.
macro(coopdyn_find_kdl)
  find_package(orocos_kdl QUIET)
  set(COOPDYN_HAVE_KDL FALSE)
  set(COOPDYN_HAVE_KDL_PARSER FALSE)
  if(orocos_kdl_FOUND)
    set(COOPDYN_HAVE_KDL TRUE)
    set(COOPDYN_KDL_LIBRARIES ${orocos_kdl_LIBRARIES})
    if(COOPDYN_WITH_KDL_PARSER)
      find_path(COOPDYN_KDL_PARSER_INCLUDE_DIR kdl_parser/kdl_parser.hpp)
      find_path(COOPDYN_URDF_MODEL_INCLUDE_DIR urdf_model/model.h)
      find_library(COOPDYN_KDL_PARSER_LIBRARY kdl_parser)
      if(COOPDYN_KDL_PARSER_INCLUDE_DIR AND COOPDYN_URDF_MODEL_INCLUDE_DIR AND COOPDYN_KDL_PARSER_LIBRARY)
        set(COOPDYN_HAVE_KDL_PARSER TRUE)
        set(COOPDYN_KDL_PARSER_LIBRARIES kdl_parser)
      endif()
    endif()
  endif()
endmacro()
