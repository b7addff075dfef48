#include "avm/io/JsonWriter.h"

#include <cmath>
#include <cstdio>

namespace avm::io
{
void JsonWriter::prefix(std::string_view key)
{
	if (m_first.size() > 1)
	{
		m_out += m_first.back() ? "\n" : ",\n";
		m_out.append(2 * (m_first.size() - 1), ' ');
	}
	m_first.back() = false;
	if (m_first.size() > 1 && !m_isArray.back()) m_out += quoted(key) + ": ";
}

void JsonWriter::open(std::string_view key, char bracket)
{
	prefix(key);
	m_out += bracket;
	m_first.push_back(true);
	m_isArray.push_back(bracket == '[');
}

void JsonWriter::close(char bracket)
{
	const bool empty = m_first.back();
	m_first.pop_back();
	m_isArray.pop_back();
	if (!empty)
	{
		m_out += "\n";
		m_out.append(2 * (m_first.size() - 1), ' ');
	}
	m_out += bracket;
	if (m_first.size() == 1) m_out += "\n";
}

JsonWriter& JsonWriter::beginObject(std::string_view key) { return open(key, '{'), *this; }
JsonWriter& JsonWriter::endObject() { return close('}'), *this; }
JsonWriter& JsonWriter::beginArray(std::string_view key) { return open(key, '['), *this; }
JsonWriter& JsonWriter::endArray() { return close(']'), *this; }

JsonWriter& JsonWriter::value(std::string_view key, double v)
{
	if (!std::isfinite(v)) return null(key);  // JSON has no NaN or infinity
	prefix(key);
	char buf[32];
	std::snprintf(buf, sizeof(buf), "%.6g", v);
	m_out += buf;
	return *this;
}

JsonWriter& JsonWriter::value(std::string_view key, long long v)
{
	prefix(key);
	m_out += std::to_string(v);
	return *this;
}

JsonWriter& JsonWriter::value(std::string_view key, bool v)
{
	prefix(key);
	m_out += v ? "true" : "false";
	return *this;
}

JsonWriter& JsonWriter::value(std::string_view key, std::string_view v)
{
	prefix(key);
	m_out += quoted(v);
	return *this;
}

JsonWriter& JsonWriter::null(std::string_view key)
{
	prefix(key);
	m_out += "null";
	return *this;
}

std::string JsonWriter::quoted(std::string_view s)
{
	std::string q = "\"";
	for (const char c : s)
	{
		if (c == '"' || c == '\\')
			q += std::string("\\") + c;
		else if (static_cast<unsigned char>(c) < 0x20)
		{
			char buf[8];
			std::snprintf(buf, sizeof(buf), "\\u%04x", c);
			q += buf;
		}
		else
			q += c;
	}
	return q + "\"";
}
}  // namespace avm::io
