// The checkpoint stream of the odometry state: raw little-endian values,
// doubles bit-exact, every read checked (a short stream is an error).
#pragma once

#include <mrpt/serialization/CArchive.h>

#include <Eigen/Geometry>

#include <stdexcept>
#include <string>

namespace avm::odometry::detail
{
inline std::runtime_error badState(const std::string& why)
{
	return std::runtime_error("VisualOdometry::loadState: " + why);
}

template <typename T>
void write(mrpt::serialization::CArchive& out, const T* values, std::size_t n)
{
	out.WriteBufferFixEndianness(values, n);
}

/** Reads n values. MRPT throws when no byte is left but returns a short
 *  count when only some are: both are a truncated stream. */
template <typename T>
void read(mrpt::serialization::CArchive& in, T* values, std::size_t n)
{
	std::size_t bytes = 0;
	try
	{
		bytes = in.ReadBufferFixEndianness(values, n);
	}
	catch (const std::exception&)
	{
	}
	if (bytes != n * sizeof(T)) throw badState("truncated odometry state (the stream ends early)");
}

template <typename T>
T read(mrpt::serialization::CArchive& in)
{
	T value;
	read(in, &value, 1);
	return value;
}

inline void writePose(mrpt::serialization::CArchive& out, const Eigen::Isometry3d& T)
{
	write(out, T.matrix().data(), 16);
}

inline Eigen::Isometry3d readPose(mrpt::serialization::CArchive& in)
{
	Eigen::Isometry3d T;
	read(in, T.matrix().data(), 16);
	if (!T.matrix().allFinite()) throw badState("corrupt odometry state (a pose is not finite)");
	return T;
}
}  // namespace avm::odometry::detail
