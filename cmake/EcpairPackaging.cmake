# Installation where Debian expects it, and a .deb made by CPack from it:
#
#   /usr/bin                 ecpaird, ecpair-linkguard (ecpaird starts the one next to it),
#                            ecpairctl, ecsim, ecsim-make-eni
#   /etc/ecpair              the example pair configuration (conffiles)
#   /lib/systemd/system      ecpaird@.service (its ExecStart points at /usr/bin)
#   /usr/share/doc/ecpair    README.md and docs/
#
# The default prefix is /usr, so `cmake --install build` (as root) installs
# the system the package installs, and `DESTDIR=/tmp/root cmake --install
# build` stages it; the package always has prefix /usr. `cpack -G DEB` (in the build tree) makes
# ecpair_<version>_<arch>.deb; its runtime dependencies come from
# dpkg-shlibdeps (package dpkg-dev) over the installed programs.

if(CMAKE_INSTALL_PREFIX_INITIALIZED_TO_DEFAULT)
  set(CMAKE_INSTALL_PREFIX "/usr" CACHE PATH "Installation prefix" FORCE)
endif()
include(GNUInstallDirs)
# Debian's places, whatever the prefix: the configuration and the unit are
# found there by ecpaird@.service and by systemd.
set(ECPAIR_CONFIG_DIR "/etc/ecpair" CACHE PATH "Where the example configuration goes")
set(ECPAIR_SYSTEMD_UNIT_DIR "/lib/systemd/system" CACHE PATH "Where the systemd unit goes (Debian 12: /lib/systemd/system)")

install(TARGETS ecpaird ecpair-linkguard ecpairctl ecsim ecsim-make-eni RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")

set(_ecpair_conffiles "")
foreach(_config controller-a.textproto controller-b.textproto)
  install(FILES "deploy/config/${_config}" DESTINATION "${ECPAIR_CONFIG_DIR}")
  string(APPEND _ecpair_conffiles "${ECPAIR_CONFIG_DIR}/${_config}\n")
endforeach()

# The unit in deploy/systemd names /usr/local/bin (a hand-made install);
# the installed copy names the binaries where this install puts them. It is
# made when installing, so a package (CPack installs with prefix /usr) and
# `cmake --install --prefix P` both get the right path.
install(CODE "
  file(READ \"${PROJECT_SOURCE_DIR}/deploy/systemd/ecpaird@.service\" unit)
  string(REPLACE \"/usr/local/bin/\" \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}/\" unit \"\${unit}\")
  file(WRITE \"${PROJECT_BINARY_DIR}/packaging/ecpaird@.service\" \"\${unit}\")
  file(INSTALL \"${PROJECT_BINARY_DIR}/packaging/ecpaird@.service\" DESTINATION \"${ECPAIR_SYSTEMD_UNIT_DIR}\")
")

install(FILES README.md DESTINATION "${CMAKE_INSTALL_DOCDIR}")
install(DIRECTORY docs/ DESTINATION "${CMAKE_INSTALL_DOCDIR}/docs" FILES_MATCHING PATTERN "*.md")

file(WRITE "${PROJECT_BINARY_DIR}/packaging/conffiles" "${_ecpair_conffiles}")

set(CPACK_GENERATOR "DEB")
set(CPACK_PACKAGE_NAME "ecpair")
set(CPACK_PACKAGE_VENDOR "ecpair")
set(CPACK_PACKAGE_CONTACT "ecpair developers <ecpair@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "redundant EtherCAT master pair and EtherCAT slave simulator")
set(CPACK_PACKAGE_DESCRIPTION
    "Two controllers run one master each on one ENI: the ACTIVE owns the bus, the INACTIVE stores and forwards "
    "every frame, mirrors the process image and takes over. ecsim simulates the slaves on network interfaces.")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION "net")
set(CPACK_DEBIAN_PACKAGE_PRIORITY "optional")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_COMPRESSION_TYPE gzip)  # xz would add a minute of CI for a few hundred KiB
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA "${PROJECT_BINARY_DIR}/packaging/conffiles")
include(CPack)
