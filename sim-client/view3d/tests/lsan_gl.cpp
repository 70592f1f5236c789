// Leak checking (LSan, CI's sanitizer stage) in test programs that open an X display and a Mesa
// GL context in-process: the D-Bus connection SDL's X11 backend opens, SDL's own video and
// audio state and Mesa's GL driver (with its LLVM) keep allocations to the end of the process
// that are not ours. The driver is kept loaded to the end, so that its frames have names when
// LSan reports, and those libraries are suppressed by name: the project's own code stays
// checked.
#include <dlfcn.h>

#include <initializer_list>

extern "C" const char* __lsan_default_suppressions() {
  return "leak:libdbus-1.so\n"
         "leak:libGLX_mesa.so\n"
         "leak:swrast_dri.so\n"
         "leak:libLLVM\n"
         "leak:libX11.so\n"
         "leak:libSDL2-2.0.so\n";
}

namespace {

struct KeepGlDriverLoaded {
  KeepGlDriverLoaded() {
    for (const char* lib : {"libGLX_mesa.so.0", "/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so",
                            "/usr/lib/dri/swrast_dri.so"})
      dlopen(lib, RTLD_NOW | RTLD_GLOBAL | RTLD_NODELETE);
  }
} keep;

}  // namespace
