// The image family's variant table (shadowmaps/variants.h) against the dh dispatch and the knob
// list: one enumeration of the variants, the others checked against it.
#include "shadowmaps/filtered_shadow_dh.h"
#include "shadowmaps/shadow_map.h"
#include "shadowmaps/variants.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

using namespace stsv;

namespace {

const ShadowMapKnob* knobNamed(const std::string& name) {
    for (const ShadowMapKnob& k : shadowMapKnobs())
        if (name == k.name) return &k;
    return nullptr;
}

} // namespace

TEST(ShadowMapVariants, RowsAgreeWithTheDhDispatch) {
    std::set<uint> selectors;
    std::set<std::string> names;
    for (const ShadowMapVariant& v : shadowMapVariants()) {
        SCOPED_TRACE(v.name);
        EXPECT_NE(v.filter, ShadowMapMethod::None);
        EXPECT_TRUE(selectors.insert(uint(v.filter)).second) << "two rows of one selector";
        EXPECT_TRUE(names.insert(v.name).second) << "two rows of one name";
        EXPECT_EQ(&shadowMapVariant(v.filter), &v);
        // A row is a filtered representation exactly when the dh dispatch gives it channels.
        const bool filtered = v.representation == MapRepresentation::Filtered;
        EXPECT_EQ(filtered, filteredChannelCount(uint(v.filter), 1u) > 0u);
        if (filtered) {
            EXPECT_LE(filteredChannelCount(uint(v.filter), uint(CSM_MAX_TERMS)), FILTERED_MAX_CHANNELS);
        }
        // Blocker searches: the depth maps and the filtered representations search (always, or
        // with the searched kernel), the grid never; the transmittance functions' volumetric PCSS
        // searches its own way.
        if (filtered) {
            EXPECT_EQ(v.blockers, BlockerSearch::WithSearchedKernel);
        }
        if (v.representation == MapRepresentation::DepthGrid) {
            EXPECT_EQ(v.blockers, BlockerSearch::Never);
        }
        EXPECT_TRUE(!v.alwaysMip || filtered) << "only a filtered representation averages through mips";
    }
    EXPECT_THROW(shadowMapVariant(ShadowMapMethod::None), std::logic_error);
    EXPECT_THROW(shadowMapVariant(ShadowMapMethod(99u)), std::logic_error);
}

TEST(ShadowMapVariants, OwnKnobsAndDefaultsNameKnobsTheVariantReads) {
    std::set<std::string> named;
    for (const ShadowMapVariant& v : shadowMapVariants()) {
        SCOPED_TRACE(v.name);
        for (const char* name : v.knobs) {
            const ShadowMapKnob* k = knobNamed(name);
            ASSERT_NE(k, nullptr) << name << " is no knob";
            EXPECT_EQ(k->readers, KnobReaders::Own) << name << " is read by a kind, not named by rows";
            EXPECT_TRUE(k->readBy(v.filter)) << name;
            named.insert(name);
        }
        const ShadowMapSettings defaults = defaultShadowMapSettings(v.filter);
        for (const auto& [name, value] : v.defaults) {
            const ShadowMapKnob* k = knobNamed(name);
            ASSERT_NE(k, nullptr) << name << " is no knob";
            EXPECT_TRUE(k->readBy(v.filter))
                << "a default for a knob " << v.name << " does not read: " << name;
            EXPECT_EQ(k->get(defaults), float(value)) << name;
        }
    }
    for (const ShadowMapKnob& k : shadowMapKnobs())
        if (k.readers == KnobReaders::Own) {
            EXPECT_TRUE(named.count(k.name)) << k.name << " is read by no row";
        }
}

TEST(ShadowMapVariants, KnobKindsSelectTheVariantsTheyDid) {
    // The kinds, spelled out as the lists they replaced: a change to a row's representation or
    // search that moves a knob in or out of a method fails here.
    using F = ShadowMapMethod;
    const F hausdorff = F(SHADOW_FILTER_MSM_HAUSDORFF);
    const auto readers = [](const char* name) {
        std::set<F> out;
        for (const ShadowMapVariant& v : shadowMapVariants())
            if (knobNamed(name)->readBy(v.filter)) out.insert(v.filter);
        return out;
    };
    EXPECT_EQ(readers("sm_size"),
              (std::set<F>{F::Pcf, F::Pcss, F::Vsm, F::Esm, F::Evsm, F::Msm, hausdorff, F::Csm}));
    EXPECT_EQ(readers("fm_kernel"), (std::set<F>{F::Vsm, F::Esm, F::Evsm, F::Msm, hausdorff, F::Csm}));
    EXPECT_EQ(readers("pcss_blocker_taps"),
              (std::set<F>{F::Pcss, F::Vsm, F::Esm, F::Evsm, F::Msm, hausdorff, F::Csm}));
    EXPECT_EQ(readers("pcss_max_search"),
              (std::set<F>{F::Pcss, F::Vsm, F::Esm, F::Evsm, F::Msm, hausdorff, F::Csm, F::Vpcss}));
    EXPECT_EQ(readers("msm_bias"), (std::set<F>{F::Msm, hausdorff}));
    EXPECT_EQ(readers("avsm_nodes"), (std::set<F>{F::Avsm, F::Vpcss}));
    EXPECT_EQ(readers("vsm_bleed"), (std::set<F>{F::Vsm, F::Evsm}));
    EXPECT_EQ(readers("sm_bias").size(), shadowMapVariants().size());
}
