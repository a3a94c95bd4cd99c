#include "gpu/vulkan.h"

#include "core/error.h"

#include <dlfcn.h>

#include <cstdlib>
#include <mutex>
#include <string>

#define STSV_DEFINE_VULKAN_FUNCTION(name) PFN_##name name = nullptr;
STSV_VULKAN_FUNCTIONS(STSV_DEFINE_VULKAN_FUNCTION)
#undef STSV_DEFINE_VULKAN_FUNCTION

namespace stsv {

namespace {

/// Opens the loader and looks up every entry point: the loader exports the core API, so dlsym
/// returns the same dispatching functions a link against it would.
void openLoader() {
    const char* env = std::getenv(VULKAN_LOADER_ENV);
    const std::string name = env && *env ? env : "libvulkan.so.1";
    void* library = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        const char* why = dlerror();
        throw Error(
            "cannot open the Vulkan loader " + name + " (" + (why ? why : "unknown reason") +
            "): install it (on Debian: apt install libvulkan1 mesa-vulkan-drivers), or render without "
            "Vulkan with --backend cpu");
    }
// NOLINTBEGIN(bugprone-macro-parentheses): fn is a name, pasted and stringised, not an expression
#define STSV_LOAD_VULKAN_FUNCTION(fn)                                                                        \
    fn = reinterpret_cast<PFN_##fn>(dlsym(library, #fn));                                                    \
    if (!fn) throw Error("the Vulkan loader " + name + " lacks " #fn ": stsv needs a Vulkan 1.3 loader");
    STSV_VULKAN_FUNCTIONS(STSV_LOAD_VULKAN_FUNCTION)
#undef STSV_LOAD_VULKAN_FUNCTION
    // NOLINTEND(bugprone-macro-parentheses)
    // The library stays open for the life of the process: the pointers point into it.
}

} // namespace

void loadVulkan() {
    static std::once_flag once;
    static std::string failure;
    // A failed load is not retried: every later call reports the same error.
    std::call_once(once, [] {
        try {
            openLoader();
        } catch (const Error& e) {
            failure = e.what();
        }
    });
    if (!failure.empty()) throw Error(failure);
}

} // namespace stsv
