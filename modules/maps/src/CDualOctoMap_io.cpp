// The map's parts of the serialized stream (exact: full log-odds of every node;
// CAdaptiveOctoMap_io.cpp puts them together) and the files MRPT apps write
// with saveMetricMapRepresentationToFile().
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "RayIntegrator.h"
#include "ResolutionPolicy.h"
#include "SurfaceSketch.h"
#include "TreeOps.h"
#include "avm/io/AtomicFile.h"
#include "avm/io/RunFolder.h"
#include "avm/maps/CDualOctoMap.h"
#include "avm/maps/OcTreeFile.h"

using namespace avm;

namespace
{
void writeTreeOptionsOf(mrpt::serialization::CArchive& out, const TTreeOptions& o)
{
	out << o.resolution << o.probHit << o.probMiss << o.clampingThresMin << o.clampingThresMax << o.occupancyThres
		<< o.maxRange;
}
void readTreeOptionsOf(mrpt::serialization::CArchive& in, TTreeOptions& o)
{
	in >> o.resolution >> o.probHit >> o.probMiss >> o.clampingThresMin >> o.clampingThresMax >> o.occupancyThres >>
		o.maxRange;
}

/** octomap's own node stream (log-odds as stored), empty for an empty tree. */
void writeTree(mrpt::serialization::CArchive& out, const octomap::OcTree* tree)
{
	std::ostringstream s;
	if (tree && tree->size() > 0) tree->writeData(s);
	out << s.str();
}
std::unique_ptr<octomap::OcTree> readTree(mrpt::serialization::CArchive& in, const TTreeOptions& o)
{
	std::string data;
	in >> data;
	auto tree = detail::makeTree(o);
	if (!data.empty())
	{
		std::istringstream s(data);
		tree->readData(s);
		if (!s) throw std::runtime_error("CAdaptiveOctoMap: corrupt octree data in the serialized map");
	}
	return tree;
}

void writeAtomically(const std::string& file, const std::function<bool(const std::string&)>& write)
{
	avm::io::writeFileAtomically(file,
		[&](const std::filesystem::path& tmp)
		{
			if (!write(tmp.string())) throw std::runtime_error("CAdaptiveOctoMap: cannot write " + file);
		});
}
}  // namespace

void CDualOctoMap::writeTreeOptions(mrpt::serialization::CArchive& out) const
{
	writeTreeOptionsOf(out, m_creation.low);
	writeTreeOptionsOf(out, m_creation.high);
}

void CDualOctoMap::readTreeOptions(mrpt::serialization::CArchive& in)
{
	readTreeOptionsOf(in, m_creation.low);
	readTreeOptionsOf(in, m_creation.high);
}

void CDualOctoMap::writeRegions(mrpt::serialization::CArchive& out, const RegionRecord& record) const
{
	out.WriteAs<uint64_t>(m_insertions);
	m_policy->serializeTo(out, record);
}

void CDualOctoMap::readRegions(mrpt::serialization::CArchive& in, const RegionRecord& record)
{
	m_insertions = in.ReadAs<uint64_t>();
	m_policy = std::make_unique<detail::ResolutionPolicy>(insertionOptions.switchPolicy, m_creation.low.resolution);
	m_policy->serializeFrom(in, record);
}

void CDualOctoMap::writeSketch(mrpt::serialization::CArchive& out) const { m_sketch->serializeTo(out); }

void CDualOctoMap::readSketch(mrpt::serialization::CArchive& in)
{
	m_sketch = std::make_unique<detail::SurfaceSketch>();
	m_sketch->serializeFrom(in);
}

void CDualOctoMap::writeTrees(mrpt::serialization::CArchive& out) const
{
	writeTree(out, m_low.get());
	out.WriteAs<uint8_t>(m_high != nullptr);
	if (m_high) writeTree(out, m_high.get());
}

void CDualOctoMap::readTrees(mrpt::serialization::CArchive& in)
{
	m_low = readTree(in, m_creation.low);
	m_high = in.ReadAs<uint8_t>() ? readTree(in, m_creation.high) : nullptr;
	if (!m_integrator) m_integrator = std::make_unique<detail::RayIntegrator>();
	m_pointsCacheValid = false;
}

std::size_t CDualOctoMap::serializedBytes() const
{
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	arch << *this;
	return static_cast<std::size_t>(buf.getTotalBytesCount());
}

void CDualOctoMap::saveMetricMapRepresentationToFile(const std::string& prefix) const
{
	const auto files = io::MapFiles::ofPrefix(prefix);
	writeBinaryTree(*m_low, files.lowTree);
	writeBinaryTree(m_high ? *m_high : *detail::makeTree(m_creation.high), files.highTree);
	writeAtomically(files.scene.string(),
		[&](const std::string& tmp)
		{
			mrpt::opengl::COpenGLScene scene;
			auto objs = mrpt::opengl::CSetOfObjects::Create();
			getVisualizationInto(*objs);
			scene.insert(objs);
			return scene.saveToFile(tmp);
		});
}
