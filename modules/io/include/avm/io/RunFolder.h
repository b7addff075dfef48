// The files of an avm-map output folder, each named here and nowhere else: the
// pipeline writes them, avm-map --resume reads the checkpoint, avm-map
// --continue the session, and avm-view reads a finished run (map,
// trajectory, persons, stats).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace avm::io
{
/** The files the adaptive map writes for CMetricMap::
 *  saveMetricMapRepresentationToFile(prefix): its two trees and its 3D scene. */
struct MapFiles
{
	std::filesystem::path lowTree, highTree, scene;

	static MapFiles ofPrefix(const std::string& prefix)
	{
		return {prefix + "_low.bt", prefix + "_high.bt", prefix + ".3Dscene"};
	}
};

class RunFolder
{
   public:
	explicit RunFolder(std::filesystem::path dir) : m_dir(std::move(dir)) {}

	const std::filesystem::path& dir() const { return m_dir; }
	/** What the map is saved under: map_low.bt, map_high.bt, map.3Dscene. */
	std::string mapPrefix() const { return (m_dir / "map").string(); }
	MapFiles map() const { return MapFiles::ofPrefix(mapPrefix()); }
	std::filesystem::path trajectory() const { return m_dir / "trajectory.txt"; }
	std::filesystem::path trajectoryStatus() const { return m_dir / "trajectory_status.txt"; }
	std::filesystem::path detections() const { return m_dir / "detections.txt"; }
	std::filesystem::path persons() const { return m_dir / "persons.csv"; }
	/** Each person's last shape (avm/persons/PersonShapesPly.h). */
	std::filesystem::path personShapes() const { return m_dir / "person_shapes.ply"; }
	std::filesystem::path topPicture() const { return m_dir / "map_top.png"; }
	std::filesystem::path perspectivePicture() const { return m_dir / "map_perspective.png"; }
	std::filesystem::path stats() const { return m_dir / "stats.json"; }
	std::filesystem::path log() const { return m_dir / "avm-map.log"; }
	std::filesystem::path checkpoint() const { return m_dir / "checkpoint.bin"; }
	/** What a next run continues (avm-map --continue): the finished run's
	 *  checkpoint, its maps, persons, keyframes and trajectory. */
	std::filesystem::path session() const { return m_dir / "session.bin"; }
	/** The run's keyframes at their final poses, MRPT's CSimpleMap (observations2map). */
	std::filesystem::path keyframes() const { return m_dir / "keyframes.simplemap"; }
	/** The files of a finished run, map first (not the checkpoint, which
	 *  only an interrupted run keeps). */
	std::vector<std::filesystem::path> outputs() const
	{
		const auto m = map();
		return {m.lowTree, m.highTree, m.scene, trajectory(), trajectoryStatus(), detections(), persons(),
			personShapes(), stats(), topPicture(), perspectivePicture(), log(), keyframes(), session()};
	}

   private:
	std::filesystem::path m_dir;
};
}  // namespace avm::io
