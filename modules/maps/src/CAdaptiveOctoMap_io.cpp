// Serialization (exact: full log-odds of every node) and the files MRPT apps
// write with saveMetricMapRepresentationToFile().
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
#include "avm/maps/CAdaptiveOctoMap.h"
#include "avm/maps/OcTreeFile.h"

using namespace avm;

IMPLEMENTS_SERIALIZABLE(CAdaptiveOctoMap, CMetricMap, avm)

namespace
{
void writeTreeOptions(mrpt::serialization::CArchive& out, const CAdaptiveOctoMap::TTreeOptions& o)
{
	out << o.resolution << o.probHit << o.probMiss << o.clampingThresMin << o.clampingThresMax << o.occupancyThres
		<< o.maxRange;
}
void readTreeOptions(mrpt::serialization::CArchive& in, CAdaptiveOctoMap::TTreeOptions& o)
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
std::unique_ptr<octomap::OcTree> readTree(mrpt::serialization::CArchive& in, const CAdaptiveOctoMap::TTreeOptions& o)
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

// Version 1: per-person regions and person tracks.
uint8_t CAdaptiveOctoMap::serializeGetVersion() const { return 1; }

void CAdaptiveOctoMap::serializeTo(mrpt::serialization::CArchive& out) const
{
	out << genericMapParams;
	writeTreeOptions(out, m_creation.low);
	writeTreeOptions(out, m_creation.high);
	const auto& i = insertionOptions;
	out.WriteAs<uint8_t>(static_cast<uint8_t>(i.switchPolicy));
	out << i.regionMargin;
	out.WriteAs<uint8_t>(static_cast<uint8_t>(i.regionLifetime));
	out << i.regionEndAfterSeconds << i.personLabel << i.sighting.depthBand << i.sighting.percentile
		<< static_cast<uint64_t>(i.sighting.minPixels) << i.sighting.minDepthFraction << i.tracking.gate
		<< i.tracking.gateGrowth << i.tracking.maxGate << i.switchAtFrame << i.switchAtFraction << i.expectedFrameCount
		<< i.insertionThreads;
	out << likelihoodOptions.decimation << renderingOptions.showFreeSpace << renderingOptions.showRegions;
	out.WriteAs<uint64_t>(m_insertions);
	m_policy->serializeTo(out);
	m_tracker.serializeTo(out);
	m_sketch->serializeTo(out);
	out.WriteAs<uint8_t>(m_lastScanTime.has_value());
	out << m_lastScanTime.value_or(0.0);
	writeTree(out, m_low.get());
	out.WriteAs<uint8_t>(m_high != nullptr);
	if (m_high) writeTree(out, m_high.get());
}

void CAdaptiveOctoMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
	if (version != 1) MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
	in >> genericMapParams;
	readTreeOptions(in, m_creation.low);
	readTreeOptions(in, m_creation.high);
	auto& i = insertionOptions;
	i.switchPolicy = static_cast<SwitchPolicy>(in.ReadAs<uint8_t>());
	in >> i.regionMargin;
	const auto lifetime = in.ReadAs<uint8_t>();
	if (lifetime > static_cast<uint8_t>(RegionLifetime::Persist))
		throw std::runtime_error("CAdaptiveOctoMap: corrupt region lifetime in the serialized map");
	i.regionLifetime = static_cast<RegionLifetime>(lifetime);
	uint64_t minPixels = 0;
	in >> i.regionEndAfterSeconds >> i.personLabel >> i.sighting.depthBand >> i.sighting.percentile >> minPixels >>
		i.sighting.minDepthFraction >> i.tracking.gate >> i.tracking.gateGrowth >> i.tracking.maxGate >>
		i.switchAtFrame >> i.switchAtFraction >> i.expectedFrameCount >> i.insertionThreads;
	i.sighting.minPixels = minPixels;
	in >> likelihoodOptions.decimation >> renderingOptions.showFreeSpace >> renderingOptions.showRegions;
	m_creation.validate("serialized creationOpts");
	insertionOptions.validate("serialized insertOpts");
	m_insertions = in.ReadAs<uint64_t>();
	m_policy = std::make_unique<detail::ResolutionPolicy>(i.switchPolicy, m_creation.low.resolution);
	m_policy->serializeFrom(in);
	m_tracker = persons::PersonTracker(i.tracking);
	m_tracker.serializeFrom(in);
	m_sketch = std::make_unique<detail::SurfaceSketch>();
	m_sketch->serializeFrom(in);
	const bool hasScanTime = in.ReadAs<uint8_t>() != 0;
	double scanTime = 0;
	in >> scanTime;
	m_lastScanTime = hasScanTime ? std::optional<double>(scanTime) : std::nullopt;
	m_low = readTree(in, m_creation.low);
	m_high = in.ReadAs<uint8_t>() ? readTree(in, m_creation.high) : nullptr;
	if (!m_integrator) m_integrator = std::make_unique<detail::RayIntegrator>();
	m_pointsCacheValid = false;
}

std::size_t CAdaptiveOctoMap::serializedBytes() const
{
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	arch << *this;
	return static_cast<std::size_t>(buf.getTotalBytesCount());
}

void CAdaptiveOctoMap::saveMetricMapRepresentationToFile(const std::string& prefix) const
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
