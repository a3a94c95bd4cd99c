#include "render/vulkan/vulkan_techniques.h"

#include "core/error.h"

namespace stsv {

std::vector<DescriptorBinding> volumeFamilyBindings(const std::vector<DescriptorBinding>& own) {
    std::vector<DescriptorBinding> bindings = HullResources::bindings();
    for (const DescriptorBinding& b : DeferredFragments::bindings()) bindings.push_back(b);
    for (const DescriptorBinding& b : ClusterLists::bindings()) bindings.push_back(b);
    for (const DescriptorBinding& b : own) bindings.push_back(b);
    return bindings;
}

std::vector<std::unique_ptr<VulkanTechnique>> makeVulkanTechniques(const VulkanTechniqueContext& context) {
    std::vector<std::unique_ptr<VulkanTechnique>> techniques;
    for (const TechniqueFamily family : context.method.techniques()) {
        switch (family) {
        case TechniqueFamily::Traced:
            throw UsageError(context.method.name + " has no Vulkan technique (its rays run on the CPU)");
        case TechniqueFamily::Wedges:
            techniques.push_back(makeWedgesVulkanTechnique(context));
            break;
        case TechniqueFamily::Stsv:
            techniques.push_back(makeStsvVulkanTechnique(context));
            break;
        case TechniqueFamily::ShadowMaps:
            if (auto maps = makeShadowMapsVulkanTechnique(context)) techniques.push_back(std::move(maps));
            break;
        }
    }
    return techniques;
}

} // namespace stsv
