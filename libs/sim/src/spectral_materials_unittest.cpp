#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/material_labels.h>
#include <quasiloc/sim/materials.h>
#include <quasiloc/sim/spectral_materials.h>
#include <quasiloc/sim/surface_class.h>

using namespace quasiloc;
namespace fs = std::filesystem;

namespace
{
double meanOf(const cv::Mat& m) { return cv::mean(m)[0]; }

/** Pearson correlation of two equally sized single-channel textures. */
double textureCorrelation(const cv::Mat& a, const cv::Mat& b)
{
    cv::Mat fa, fb;
    a.convertTo(fa, CV_64F);
    b.convertTo(fb, CV_64F);
    fa -= cv::mean(fa)[0];
    fb -= cv::mean(fb)[0];
    return fa.dot(fb) / std::sqrt(fa.dot(fa) * fb.dot(fb));
}

const sim::MaterialLibrary& spectralLibrary()
{
    static const sim::MaterialLibrary lib = sim::makeMaterials(sim::MaterialSet::spectral, 7, 128);
    return lib;
}
}  // namespace

TEST(SpectralMaterials, LevelsAndCouplingFollowTheTable)
{
    const sim::MaterialLibrary& lib = spectralLibrary();
    ASSERT_EQ(lib.size(), size_t(sim::kNumMaterials));
    for (int id = 0; id < sim::kNumMaterials; ++id)
    {
        const sim::Material& m = lib[size_t(id)];
        const sim::SpectralMaterial& sp = sim::spectralMaterial(uint16_t(id));
        const cv::Mat albedo = m.albedo_mips[0];
        // Levels: the table's, up to clamping at the ends of [0, 1] and 8-bit quantisation of the albedo.
        EXPECT_NEAR(m.meanAlbedo(), sp.visible_albedo, 0.02 + 0.1 * sp.visible_albedo) << m.name;
        EXPECT_NEAR(meanOf(m.reflectivity), sp.nir_reflectance, 0.02 + 0.1 * sp.nir_reflectance) << m.name;
        // The two textures are related by the material's coupling, not copied.
        const double r = textureCorrelation(albedo, m.reflectivity);
        EXPECT_NEAR(r, sp.coupling, 0.15) << m.name;
        EXPECT_LT(r, 0.99) << m.name;
    }
}

TEST(SpectralMaterials, CameraPatternsAreTheProceduralOnesAtOtherLevels)
{
    const sim::MaterialLibrary procedural = sim::makeMaterials(sim::MaterialSet::procedural, 7, 128);
    const sim::MaterialLibrary same = sim::makeProceduralMaterials(7, 128);
    for (int id = 0; id < sim::kNumMaterials; ++id)
    {
        const sim::Material& p = procedural[size_t(id)];
        // makeProceduralMaterials is the procedural set, bit for bit.
        EXPECT_EQ(cv::norm(p.albedo_mips[0], same[size_t(id)].albedo_mips[0], cv::NORM_INF), 0.0);
        EXPECT_EQ(cv::norm(p.reflectivity, same[size_t(id)].reflectivity, cv::NORM_INF), 0.0);
        // The spectral camera texture is the procedural pattern rescaled (clamping aside).
        EXPECT_GT(textureCorrelation(p.albedo_mips[0], spectralLibrary()[size_t(id)].albedo_mips[0]), 0.9) << p.name;
    }
}

TEST(SpectralMaterials, UnknownMaterialIsAnError)
{
    EXPECT_THROW(sim::spectralMaterial(uint16_t(sim::kNumMaterials)), core::InputError);
}

TEST(SurfaceClass, EveryMaterialStandsForAStreetClass)
{
    EXPECT_EQ(sim::surfaceClassOf(sim::kFloorCarpet), sim::SurfaceClass::road);
    EXPECT_EQ(sim::surfaceClassOf(sim::kCheckerBoard), sim::SurfaceClass::marking);
    EXPECT_EQ(sim::surfaceClassOf(sim::kWallPlaster), sim::SurfaceClass::facade);
    EXPECT_EQ(sim::surfaceClassOf(sim::kCardboard), sim::SurfaceClass::vehicle);
    EXPECT_EQ(sim::surfaceClassOf(uint16_t(sim::kNumMaterials)), sim::SurfaceClass::other);
    for (int id = 0; id < sim::kNumMaterials; ++id)
        EXPECT_NE(sim::surfaceClassOf(uint16_t(id)), sim::SurfaceClass::other) << id;
    EXPECT_STREQ(sim::toString(sim::SurfaceClass::vegetation), "vegetation");
}

TEST(MaterialLabels, RoundTripAndBadFiles)
{
    const fs::path dir = fs::temp_directory_path() / "quasiloc_material_labels_unittest";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string path = (dir / sim::kMaterialLabelsFile).string();
    const std::vector<uint16_t> labels = {0, 1, 11, 258, 65535, 3};
    sim::saveMaterialLabels(path, labels);
    EXPECT_EQ(sim::loadMaterialLabels(path, labels.size()), labels);
    // A map of another size, a missing file, a foreign file and a cut one are errors naming the file.
    EXPECT_THROW(sim::loadMaterialLabels(path, labels.size() + 1), core::InputError);
    EXPECT_THROW(sim::loadMaterialLabels((dir / "missing.bin").string(), 1), core::InputError);
    {
        std::ofstream f(dir / "foreign.bin", std::ios::binary);
        f << "PLY not labels at all";
    }
    EXPECT_THROW(sim::loadMaterialLabels((dir / "foreign.bin").string(), 1), core::InputError);
    fs::resize_file(path, fs::file_size(path) - 1);
    try
    {
        sim::loadMaterialLabels(path, labels.size());
        ADD_FAILURE() << "a cut file was read";
    }
    catch (const core::InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    fs::remove_all(dir);
}
