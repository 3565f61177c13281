# Cross-building nodetrace for arm64 on Debian with its multiarch packages
# (crossbuild-essential-arm64, and the libraries as NAME:arm64), as
# scripts/test-cross.sh does: cmake -DCMAKE_TOOLCHAIN_FILE=scripts/cross/aarch64-linux-gnu.cmake
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

# Libraries and packages' CMake files from the arm64 side of the multiarch
# tree (/usr/lib/aarch64-linux-gnu), headers and programs from the host.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")
