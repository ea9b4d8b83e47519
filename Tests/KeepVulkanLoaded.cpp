// Sanitizer builds only (NRD_SANITIZE, preloaded by Tests/Sanitize.cmake): keeps the Vulkan driver
// and layers mapped until the process exits. The Vulkan loader dlcloses them when an instance is
// destroyed, after which LeakSanitizer can neither name their frames nor match them against
// Tests/lsan.supp. RTLD_LOCAL: their symbols do not interpose the loader's. A library that is not
// installed is skipped.
#include <dlfcn.h>

__attribute__((constructor)) static void KeepVulkanLoaded()
{
    const char* libraries[] = {"libvulkan_lvp.so", "libVkLayer_khronos_validation.so", "libVkLayer_MESA_device_select.so"};
    for (const char* name : libraries)
        dlopen(name, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
}
