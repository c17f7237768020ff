// The transfer kind table (transfer/kind_table.hpp) against the rules it replaced: the layout the
// baker gave each kind before the table (bake.cpp's own channels and shape rule, restated here by
// hand), the default basis sizes, the names, the shading passes and the shapes Python's arrays
// take.
#include "shprt/bake/bake.hpp"
#include "shprt/core/error.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/transfer/kind_table.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace shprt {
namespace {

constexpr TransferKind kKinds[] = {TransferKind::unshadowed, TransferKind::shadowed,
                                   TransferKind::interreflected, TransferKind::glossy};

// What bake_description made of each kind before the table (as of issue 35's main).
TransferLayout layout_before(TransferKind kind, int K) {
    TransferLayout l;
    l.domain = ReceiverDomain::vertex;
    l.channels = kind == TransferKind::interreflected ? 3 : 1;
    l.K = K;
    l.shape =
        kind == TransferKind::glossy ? TransferShape::symmetric_matrix : TransferShape::vector;
    l.encoding = TransferEncoding::f32;
    return l;
}

TEST(KindTable, EveryKindHasOneRowInOrder) {
    ASSERT_EQ(kind_rows().size(), std::size(kKinds));
    for (std::size_t i = 0; i < std::size(kKinds); ++i) {
        EXPECT_EQ(kind_rows()[i].kind, kKinds[i]);
        EXPECT_EQ(&kind_row(kKinds[i]), &kind_rows()[i]);
        EXPECT_EQ(parse_transfer_kind(kind_rows()[i].name), kKinds[i]);
        EXPECT_STREQ(to_string(kKinds[i]), kind_rows()[i].name);
    }
    EXPECT_THROW(parse_transfer_kind("specular"), Error);
}

TEST(KindTable, BakeLayoutIsTheLayoutBeforeTheTable) {
    for (const TransferKind kind : kKinds)
        for (const int K : {1, 9, 16, 25}) {
            BakeOptions options;
            options.transfer = kind;
            options.K = K;
            EXPECT_EQ(bake_description(options).layout, layout_before(kind, K)) << to_string(kind);
            EXPECT_EQ(layout_for(kind, K), layout_before(kind, K)) << to_string(kind);
        }
    EXPECT_EQ(layout_for(TransferKind::shadowed, 9, ReceiverDomain::texel).domain,
              ReceiverDomain::texel);
}

TEST(KindTable, DefaultsAndTraitsAreTheOldBranches) {
    for (const TransferKind kind : kKinds) {
        const TransferKindRow& row = kind_row(kind);
        SCOPED_TRACE(row.name);
        EXPECT_EQ(default_coeffs(kind), kind == TransferKind::glossy ? sh_count(5) : 16);
        EXPECT_EQ(row.traces_rays, kind != TransferKind::unshadowed);
        EXPECT_EQ(row.direct_part, kind == TransferKind::interreflected);
        EXPECT_EQ(row.interreflection, kind == TransferKind::interreflected);
        EXPECT_EQ(row.whole_domain, kind == TransferKind::interreflected);
        EXPECT_EQ(row.error_bounded, kind != TransferKind::glossy);
        EXPECT_EQ(is_matrix(row), kind == TransferKind::glossy);
        EXPECT_EQ(row.cosine, kind != TransferKind::glossy);
        // A local set's density follows the cosine: uniform on the hemisphere without it.
        BakeOptions o;
        o.transfer = kind;
        o.samples = 4;
        const DirectionSet set = bake_direction_set(o);
        EXPECT_FLOAT_EQ(set.weights[0], float((row.cosine ? 1.0 : 2.0) * 3.14159265358979 / 4));
    }
}

TEST(KindTable, ShadingPassFollowsDomainAndShape) {
    TransferLayout l = layout_for(TransferKind::interreflected, 9);
    EXPECT_EQ(shading_pass(l), ShadingPass::vertex_vectors);
    l = layout_for(TransferKind::glossy, 9);
    EXPECT_EQ(shading_pass(l), ShadingPass::vertex_matrices);
    l.shape = TransferShape::matrix;
    EXPECT_EQ(shading_pass(l), ShadingPass::none);
    EXPECT_TRUE(is_matrix(l));
    EXPECT_FALSE(is_glossy_matrix(l));
    l = layout_for(TransferKind::glossy, 9, ReceiverDomain::texel);
    EXPECT_EQ(shading_pass(l), ShadingPass::texels);
    EXPECT_STREQ(to_string(ShadingPass::vertex_matrices), "vertex_matrices");
}

// The shapes Python's arrays take per receiver, and their inverse for a matrix kind.
TEST(KindTable, ReceiverShapesAndTheirInverse) {
    using Shape = std::vector<std::size_t>;
    EXPECT_EQ(receiver_shape(layout_for(TransferKind::shadowed, 16)), Shape{16});
    EXPECT_EQ(receiver_shape(layout_for(TransferKind::interreflected, 16)), (Shape{3, 16}));
    EXPECT_EQ(receiver_shape(layout_for(TransferKind::glossy, 9)), Shape{45});
    TransferLayout full = layout_for(TransferKind::glossy, 4);
    full.shape = TransferShape::matrix;
    EXPECT_EQ(receiver_shape(full), (Shape{4, 4}));
    for (const int K : {1, 2, 9, 25, 64}) {
        const TransferLayout l = layout_for(TransferKind::glossy, K);
        EXPECT_EQ(basis_size_of(l.shape, l.floats_per_channel()), K);
        EXPECT_EQ(basis_size_of(TransferShape::matrix, std::size_t(K) * K), K);
        EXPECT_EQ(basis_size_of(TransferShape::vector, std::size_t(K)), K);
    }
    EXPECT_EQ(basis_size_of(TransferShape::symmetric_matrix, 0), -1);
    EXPECT_EQ(basis_size_of(TransferShape::symmetric_matrix, 4), -1);  // between 3 and 6
    EXPECT_EQ(basis_size_of(TransferShape::matrix, 5), -1);
}

}  // namespace
}  // namespace shprt
