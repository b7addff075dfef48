#include "CViewVoxels.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_set>

namespace avm::viewer
{
namespace
{
/** A voxel's place: its centre in units of its edge (octree centres lie at
 *  (k + 1/2) edges, so the floor is k) and the edge's bits. */
struct Cell
{
	std::int64_t i[3];
	std::uint32_t edge;
	bool operator==(const Cell& o) const
	{
		return i[0] == o.i[0] && i[1] == o.i[1] && i[2] == o.i[2] && edge == o.edge;
	}
};

struct CellHash
{
	std::size_t operator()(const Cell& c) const
	{
		std::size_t h = c.edge;
		for (const auto v : c.i) h = h * 1000003u ^ std::hash<std::int64_t>()(v);
		return h;
	}
};

Cell cellOf(const mrpt::math::TPoint3Df& centre, float edge)
{
	Cell c{};
	for (int a = 0; a < 3; ++a) c.i[a] = static_cast<std::int64_t>(std::floor(centre[a] / edge));
	std::memcpy(&c.edge, &edge, sizeof(edge));
	return c;
}
}  // namespace

void CViewVoxels::clearVoxels(unsigned set)
{
	m_voxel_sets.at(set).voxels.clear();
	notifyChange();
}

void CViewVoxels::onUpdateBuffers_Points()
{
	std::unique_lock<std::shared_mutex> lock(CRenderizableShaderPoints::m_pointsMtx.data);
	CRenderizableShaderPoints::m_vertex_buffer_data.clear();
	CRenderizableShaderPoints::m_color_buffer_data.clear();
}

void CViewVoxels::onUpdateBuffers_Triangles()
{
	std::unique_lock<std::shared_mutex> lock(CRenderizableShaderTriangles::m_trianglesMtx.data);
	auto& tris = CRenderizableShaderTriangles::m_triangles;
	tris.clear();  // keeps the capacity of the last update
	std::unordered_set<Cell, CellHash> cells;
	for (const auto& set : m_voxel_sets)
	{
		if (!set.visible) continue;
		cells.clear();
		for (const auto& v : set.voxels) cells.insert(cellOf(v.coords, static_cast<float>(v.side_length)));
		for (const auto& v : set.voxels)
		{
			const float edge = static_cast<float>(v.side_length), h = 0.5f * edge;
			const Cell cell = cellOf(v.coords, edge);
			for (int axis = 0; axis < 3; ++axis)
				for (const int sign : {1, -1})
				{
					Cell next = cell;
					next.i[axis] += sign;
					if (cells.count(next)) continue;  // the neighbour covers this face
					// The face's corners: axes u, v follow `axis` cyclically,
					// so u x v points along +axis; the order turns round the
					// outward normal.
					const int u = (axis + 1) % 3, w = (axis + 2) % 3;
					mrpt::math::TVector3Df normal(0, 0, 0);
					mrpt::math::TPoint3Df corner[4];
					normal[axis] = float(sign);
					const float du[4] = {-h, h, h, -h}, dw[4] = {-h, -h, h, h};
					for (int k = 0; k < 4; ++k)
					{
						corner[k] = v.coords;
						corner[k][axis] += sign * h;
						corner[k][u] += sign * du[k];
						corner[k][w] += dw[k];
					}
					for (const auto& [a, b, c] : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}})
					{
						mrpt::opengl::TTriangle t(corner[a], corner[b], corner[c], normal, normal, normal);
						t.setColor(v.color);
						tris.emplace_back(std::move(t));
					}
				}
		}
	}
}
}  // namespace avm::viewer
