# Installing lidarscout as users install tools: `cmake --install build --prefix P` puts the
# program in P/bin, its plugins in P/lib/lidarscout, the shipped model in
# P/share/lidarscout/models, the page of `serve` in P/share/lidarscout/web and a desktop entry for the viewer in P/share/applications; the
# installed program finds them from its own location (core/plugin_paths, nn/heightmap_network).
# CPack makes a .deb whose dependencies are the Debian runtime packages (dpkg-shlibdeps).
include(GNUInstallDirs)
install(TARGETS lidarscout RUNTIME DESTINATION bin)
install(TARGETS lidarscout_torch LIBRARY DESTINATION lib/lidarscout)
if(TARGET lidarscout_cuda_raster)
  install(TARGETS lidarscout_cuda_raster LIBRARY DESTINATION lib/lidarscout)
endif()
# The Python module where Debian's python3 looks for it under the prefix the install is given (chosen when it
# runs: `cmake --install --prefix` and CPack set the prefix then): lib/python3/dist-packages for /usr (Debian's
# packaged modules; also CPack's staged .../usr of the .deb), lib/python3.X/dist-packages for /usr/local (the
# default prefix: Debian's local modules), lib/python3.X/site-packages elsewhere (as for ~/.local or a venv).
set(LIDARSCOUT_PYTHON_SITE_DIR "" CACHE STRING "Where the Python module is installed (empty: by the prefix)")
set(LIDARSCOUT_PYTHON_VERSION python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR})
math(EXPR LIDARSCOUT_PYTHON_NEXT_MINOR "${Python3_VERSION_MINOR} + 1")
install(CODE "
  if(NOT \"${LIDARSCOUT_PYTHON_SITE_DIR}\" STREQUAL \"\")
    set(LIDARSCOUT_PYTHON_DESTINATION \"${LIDARSCOUT_PYTHON_SITE_DIR}\")
  elseif(CMAKE_INSTALL_PREFIX MATCHES \"(^|/)usr/*$\")
    set(LIDARSCOUT_PYTHON_DESTINATION lib/python3/dist-packages)
  elseif(CMAKE_INSTALL_PREFIX MATCHES \"(^|/)usr/local/*$\")
    set(LIDARSCOUT_PYTHON_DESTINATION lib/${LIDARSCOUT_PYTHON_VERSION}/dist-packages)
  else()
    set(LIDARSCOUT_PYTHON_DESTINATION lib/${LIDARSCOUT_PYTHON_VERSION}/site-packages)
  endif()")
install(TARGETS lidarscout_python_module LIBRARY DESTINATION \${LIDARSCOUT_PYTHON_DESTINATION}/lidarscout)
install(FILES ${LIDARSCOUT_PYTHON_SOURCES} DESTINATION \${LIDARSCOUT_PYTHON_DESTINATION}/lidarscout)
install(FILES ${LIDARSCOUT_DASK_SOURCES} DESTINATION \${LIDARSCOUT_PYTHON_DESTINATION}/lidarscout_dask)  # (its driver)
install(FILES models/heightmap_cnn.pt models/README.md DESTINATION share/lidarscout/models)
install(FILES packaging/lidarscout.desktop DESTINATION share/applications)
# The page of `lidarscout serve` (serve/web_assets.cpp finds it beside the program's share/).
file(GLOB LIDARSCOUT_WEB_FILES ${CMAKE_SOURCE_DIR}/web/*.html ${CMAKE_SOURCE_DIR}/web/*.js ${CMAKE_SOURCE_DIR}/web/*.css)
install(FILES ${LIDARSCOUT_WEB_FILES} DESTINATION share/lidarscout/web)
install(FILES README.md DESTINATION share/doc/lidarscout)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME lidarscout)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "lidarscout developers <lidarscout@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Explore country-sized LAS/LAZ lidar scans in seconds, without preprocessing")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # depends on the Debian packages of the libraries it links
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${CMAKE_BINARY_DIR})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
# The Python module (built for this python3.X, its ABI in the file name) needs that Python and numpy; the
# program does not: recommended, not required.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3 (>= ${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}), \
python3 (<< ${Python3_VERSION_MAJOR}.${LIDARSCOUT_PYTHON_NEXT_MINOR}), python3-numpy")
include(CPack)
