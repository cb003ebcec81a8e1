// Bytes on the wire: status lines, response headers and chunked multipart
// framing, written into reusable strings so the hot path does not allocate
// once their capacity has grown.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace mtc::bridge::detail {

struct HeadFields {
  int status = 200;
  unsigned version = 11;  // 10 or 11, as the request said
  std::string_view content_type;
  std::size_t content_length = 0;
  bool keep_alive = true;
  std::string_view server_name;
};

// "HTTP/1.1 200 OK\r\n...\r\n\r\n" for a response with a body of known size.
void write_head(std::string& out, const HeadFields& fields);

// Head of a streaming answer: multipart/x-mixed-replace, chunked.
void write_stream_head(std::string& out, std::string_view boundary, std::string_view server_name);

// Appends the chunk header plus the MIME part header of one multipart part
// whose body has `body_size` bytes; the chunk ends with kPartTail after the
// body.
void write_part_head(std::string& out, std::string_view boundary, std::string_view content_type,
                     std::size_t body_size);
inline constexpr std::string_view kPartTail = "\r\n\r\n";  // part CRLF + chunk CRLF

// Closing boundary and the terminating zero-size chunk.
void write_stream_end(std::string& out, std::string_view boundary);

// A boundary no XML document will contain (random hex, 32 characters).
std::string make_boundary();

// Reason phrase for a status; never empty.
std::string_view reason_phrase(int status) noexcept;

}  // namespace mtc::bridge::detail
