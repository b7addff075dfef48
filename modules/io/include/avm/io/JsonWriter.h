// A small streaming JSON writer, for avm-map's stats.json (MRPT's yaml reads JSON but
// does not write it).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace avm::io
{
class JsonWriter
{
   public:
	JsonWriter() { m_first.push_back(true); }
	/** Opens an object; the key is ignored inside arrays and at the top level. */
	JsonWriter& beginObject(std::string_view key = {});
	JsonWriter& endObject();
	JsonWriter& beginArray(std::string_view key = {});
	JsonWriter& endArray();
	JsonWriter& value(std::string_view key, double v);
	JsonWriter& value(std::string_view key, long long v);
	JsonWriter& value(std::string_view key, std::size_t v) { return value(key, static_cast<long long>(v)); }
	JsonWriter& value(std::string_view key, int v) { return value(key, static_cast<long long>(v)); }
	JsonWriter& value(std::string_view key, bool v);
	JsonWriter& value(std::string_view key, std::string_view v);
	JsonWriter& value(std::string_view key, const char* v) { return value(key, std::string_view(v)); }
	JsonWriter& null(std::string_view key);
	/** The value, or null when there is none. */
	template <typename T>
	JsonWriter& value(std::string_view key, const std::optional<T>& v)
	{
		return v ? value(key, *v) : null(key);
	}
	/** Array elements (no key). */
	JsonWriter& element(double v) { return value({}, v); }
	const std::string& str() const { return m_out; }

   private:
	void open(std::string_view key, char bracket);
	void close(char bracket);
	void prefix(std::string_view key);
	static std::string quoted(std::string_view s);

	std::string m_out;
	std::vector<bool> m_first;  //!< per open container: no element written yet
	std::vector<bool> m_isArray{false};
};
}  // namespace avm::io
