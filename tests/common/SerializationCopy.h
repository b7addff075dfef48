// Test helper: one object's state into another through its own
// serializeTo / serializeFrom (the pieces a checkpoint is made of), via an
// in-memory MRPT archive.
#pragma once

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <string>

namespace avm::test
{
/** Writes `from` with serializeTo(archive) and reads it into `into` with
 *  serializeFrom(archive). */
template <typename T>
void copyBySerialization(const T& from, T& into)
{
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	from.serializeTo(arch);
	buf.Seek(0);
	into.serializeFrom(arch);
}

/** The bytes of `object` as an MRPT archive streams it (class name, version
 *  and state): two objects with the same bytes hold the same state. */
inline std::string serializedBytes(const mrpt::serialization::CSerializable& object)
{
	mrpt::io::CMemoryStream buf;
	auto arch = mrpt::serialization::archiveFrom(buf);
	arch << object;
	return std::string(static_cast<const char*>(buf.getRawBufferData()), buf.getTotalBytesCount());
}
}  // namespace avm::test
