// The flat-BVH tracer: the SHPRT_HD traversal of flat_bvh.hpp (the code the CUDA kernels run)
// driven from the CPU, so the GPU's BVH and traversal are tested against Embree without a GPU.
#include "shprt/trace/bvh_build.hpp"
#include "shprt/trace/flat_bvh.hpp"
#include "shprt/trace/tracer.hpp"

namespace shprt {

namespace {

class FlatBvhTracer final : public Tracer {
public:
    explicit FlatBvhTracer(const Mesh& mesh) : m_bvh(build_flat_bvh(mesh)), m_view(m_bvh.view()) {}

    void occluded(Vec3f origin, const Vec3f* dirs, int count, float tnear, float tfar,
                  std::uint8_t* occluded) const override {
        for (int i = 0; i < count; ++i)
            occluded[i] = bvh_occluded(m_view, origin, dirs[i], tnear, tfar) ? 1 : 0;
    }

    Hit intersect(Vec3f origin, Vec3f dir, float tnear, float tfar) const override {
        return bvh_intersect(m_view, origin, dir, tnear, tfar);
    }

    const char* name() const override { return "flat-bvh"; }
    std::size_t memory_bytes() const override { return m_bvh.bytes(); }

private:
    FlatBvh m_bvh;
    FlatBvhView m_view;
};

}  // namespace

std::unique_ptr<Tracer> make_flat_bvh_tracer(const Mesh& mesh) {
    return std::make_unique<FlatBvhTracer>(mesh);
}

}  // namespace shprt
