# Use ccache for every compile when it is installed. Paths under the source tree are hashed
# relative to it (CCACHE_BASEDIR) and the build directory is left out of the hash
# (CCACHE_NOHASHDIR, which -g would otherwise add), so another clone of the same tree — CI's clean
# clone — hits the objects a developer's build has already compiled. Debug information then names
# the directory of whichever clone compiled the object first. Three builds of the tree (the build, ASan and TSan) fit in the 12 GB
# cache.
find_program(CCACHE_PROGRAM ccache)
if(CCACHE_PROGRAM)
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_BASEDIR=${CMAKE_SOURCE_DIR}
                                  CCACHE_NOHASHDIR=1 CCACHE_MAXSIZE=12G ${CCACHE_PROGRAM})
  message(STATUS "ccache: ${CCACHE_PROGRAM} (base dir ${CMAKE_SOURCE_DIR})")
endif()
