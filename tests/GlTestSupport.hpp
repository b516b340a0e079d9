// Shared by the tests that open GL windows (test_gl, test_sim2d).
#pragma once

#include <dlfcn.h>
#include <link.h>

#include <string>
#include <vector>

namespace rgvc::gl_test {

/// Keeps every library loaded now mapped until exit (RTLD_NODELETE). Closing the display unloads Mesa's
/// DRI driver (swrast_dri.so) and glfwTerminate the X extension libraries, while allocations of theirs
/// live on; LeakSanitizer then reports them from an "<unknown module>" that tests/lsan.supp cannot name.
/// Pinned, they stay mapped and their allocations are suppressed by library, as everywhere else.
inline void pinLoadedLibraries() {
    std::vector<std::string> names;
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void* out) {
            if (info->dlpi_name && info->dlpi_name[0]) static_cast<std::vector<std::string>*>(out)->push_back(info->dlpi_name);
            return 0;
        },
        &names);
    for (const std::string& n : names) (void)dlopen(n.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);
}

} // namespace rgvc::gl_test
