// MRPT's TPoint3D and TBoundingBox in an archive, as three and six doubles.
// MRPT packs TPoint3D (#pragma pack(1)): inside another structure (an
// optional after a 4-byte member, say) its doubles can sit 4-byte aligned,
// where streaming them through CArchive's double& is undefined (UBSan
// reports it), so they go through aligned copies.
#pragma once

#include <mrpt/math/TBoundingBox.h>
#include <mrpt/math/TPoint3D.h>
#include <mrpt/serialization/CArchive.h>

namespace avm::io
{
inline void writePoint(mrpt::serialization::CArchive& out, const mrpt::math::TPoint3D& p)
{
	const double x = p.x, y = p.y, z = p.z;
	out << x << y << z;
}
inline void readPoint(mrpt::serialization::CArchive& in, mrpt::math::TPoint3D& p)
{
	double x = 0, y = 0, z = 0;
	in >> x >> y >> z;
	p = {x, y, z};
}
inline void writeBox(mrpt::serialization::CArchive& out, const mrpt::math::TBoundingBox& b)
{
	writePoint(out, b.min);
	writePoint(out, b.max);
}
inline void readBox(mrpt::serialization::CArchive& in, mrpt::math::TBoundingBox& b)
{
	readPoint(in, b.min);
	readPoint(in, b.max);
}
}  // namespace avm::io
