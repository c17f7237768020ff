// The transfer layout: floats per receiver for every shape, offsets, validation, names, and the
// one check of a transfer against its mesh.
#include "shprt/core/error.hpp"
#include "shprt/scene/mesh.hpp"
#include "shprt/transfer/transfer.hpp"

#include <gtest/gtest.h>

namespace shprt {
namespace {

TransferLayout layout(int K, int channels, TransferShape shape) {
    TransferLayout l;
    l.K = K;
    l.channels = channels;
    l.shape = shape;
    return l;
}

TEST(TransferLayout, FloatsPerReceiverForEveryShape) {
    EXPECT_EQ(layout(16, 1, TransferShape::vector).floats_per_receiver(), 16u);
    EXPECT_EQ(layout(16, 3, TransferShape::vector).floats_per_receiver(), 48u);
    EXPECT_EQ(layout(25, 1, TransferShape::matrix).floats_per_receiver(), 625u);
    EXPECT_EQ(layout(25, 3, TransferShape::matrix).floats_per_receiver(), 1875u);
    EXPECT_EQ(layout(25, 1, TransferShape::symmetric_matrix).floats_per_receiver(), 325u);
    EXPECT_EQ(layout(1, 1, TransferShape::symmetric_matrix).floats_per_receiver(), 1u);
    EXPECT_EQ(layout(32, 3, TransferShape::vector).floats(1000), 96000u);
}

TEST(TransferLayout, OffsetIsReceiverMajorThenChannel) {
    const TransferLayout l = layout(9, 3, TransferShape::vector);
    EXPECT_EQ(l.offset(0), 0u);
    EXPECT_EQ(l.offset(0, 2), 18u);
    EXPECT_EQ(l.offset(5, 1), (5u * 3 + 1) * 9);
    const TransferLayout m = layout(4, 3, TransferShape::symmetric_matrix);
    EXPECT_EQ(m.offset(2, 1), (2u * 3 + 1) * 10);
}

TEST(TransferLayout, ValidateRefusesWhatNoReaderCanUse) {
    EXPECT_NO_THROW(layout(1, 1, TransferShape::vector).validate());
    EXPECT_NO_THROW(layout(kMaxTransferK, 3, TransferShape::vector).validate());
    EXPECT_THROW(layout(0, 1, TransferShape::vector).validate(), Error);
    EXPECT_THROW(layout(kMaxTransferK + 1, 1, TransferShape::vector).validate(), Error);
    EXPECT_THROW(layout(16, 2, TransferShape::vector).validate(), Error);
    EXPECT_THROW(layout(16, 0, TransferShape::vector).validate(), Error);
}

TEST(TransferLayout, NamesRoundTrip) {
    for (TransferShape s :
         {TransferShape::vector, TransferShape::matrix, TransferShape::symmetric_matrix})
        EXPECT_EQ(parse_transfer_shape(to_string(s)), s);
    for (TransferEncoding e : {TransferEncoding::f32, TransferEncoding::f16})
        EXPECT_EQ(parse_transfer_encoding(to_string(e)), e);
    for (ReceiverDomain d : {ReceiverDomain::vertex, ReceiverDomain::texel})
        EXPECT_EQ(parse_receiver_domain(to_string(d)), d);
    for (TransferKind k : {TransferKind::shadowed, TransferKind::unshadowed})
        EXPECT_EQ(parse_transfer_kind(to_string(k)), k);
    EXPECT_THROW(parse_transfer_shape("tensor"), Error);
    EXPECT_THROW(parse_transfer_encoding("float64"), Error);
    EXPECT_THROW(parse_receiver_domain("voxel"), Error);
}

Mesh three_vertices() {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    m.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
    m.albedo = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
    m.triangles = {{0, 2, 1}};
    return m;
}

TEST(TransferSetCheck, OneRowPerVertexOfTheLayout) {
    const Mesh mesh = three_vertices();
    TransferInfo info;
    info.layout = layout(4, 3, TransferShape::vector);
    TransferSet t = TransferSet::zeros(info, 3);
    EXPECT_EQ(t.coeffs.size(), 36u);
    EXPECT_EQ(t.receiver_count(), 3u);
    EXPECT_EQ(t.receiver(2, 1) - t.coeffs.data(), 28);
    EXPECT_NO_THROW(t.check(mesh));
    t.coeffs.pop_back();
    EXPECT_THROW(t.check(mesh), Error) << "a short transfer";
    t = TransferSet::zeros(info, 4);
    EXPECT_THROW(t.check(mesh), Error) << "one row too many";
    t = TransferSet::zeros(info, 3);
    Mesh no_albedo = mesh;
    no_albedo.albedo.clear();
    EXPECT_THROW(t.check(no_albedo), Error);
    t.layout.channels = 2;
    EXPECT_THROW(t.check(mesh), Error) << "an invalid layout";
    info.layout.K = 0;
    EXPECT_THROW(TransferSet::zeros(info, 3), Error);
}

}  // namespace
}  // namespace shprt
