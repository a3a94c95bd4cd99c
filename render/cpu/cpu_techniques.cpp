#include "render/cpu/cpu_techniques.h"

#include "core/timer.h"
#include "reference/embree_scene.h"
#include "reference/reference_visibility.h"

namespace stsv {

namespace {

/// The ground truth: Embree shadow rays to every sample.
class TracedTechnique final : public CpuTechnique {
  public:
    explicit TracedTechnique(const CpuTechniqueContext& c) : m_c(c) {}
    void run(CpuLightWork& work) override {
        Timer timer;
        traceReferenceSamples(m_c.embree, work.gbuffer, work.light, m_c.plan, m_c.farDistance, work.samples);
        work.passes[work.pass("reference")] = timer.milliseconds();
    }
    void takeStats(nlohmann::json&) override {}

  private:
    const CpuTechniqueContext& m_c;
};

} // namespace

std::vector<std::unique_ptr<CpuTechnique>> makeCpuTechniques(const CpuTechniqueContext& context) {
    std::vector<std::unique_ptr<CpuTechnique>> techniques;
    for (const TechniqueFamily family : context.method.techniques()) {
        switch (family) {
        case TechniqueFamily::Traced:
            techniques.push_back(std::make_unique<TracedTechnique>(context));
            break;
        case TechniqueFamily::Wedges:
            techniques.push_back(makeWedgesCpuTechnique(context));
            break;
        case TechniqueFamily::Stsv:
            techniques.push_back(makeStsvCpuTechnique(context));
            break;
        case TechniqueFamily::ShadowMaps:
            techniques.push_back(makeShadowMapsCpuTechnique(context));
            break;
        }
    }
    return techniques;
}

} // namespace stsv
