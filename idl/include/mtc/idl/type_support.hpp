// Type supports for the mtc topics, with an instance key that depends only on
// the key fields.
//
// fastddsgen 2.3 computes the instance handle by serialising the key fields
// into a scratch buffer that belongs to the type object and hashing it. Fast
// CDR 1.0 skips the alignment padding between two strings without writing
// it, so the padding bytes are whatever the previous key left there: the same
// (device_uuid, data_item_id) gets another handle whenever the key hashed just
// before it had different string lengths. A writer then keeps a stray
// instance per odd handle, each holding an old sample forever; its history's
// low mark stops advancing and every RTPS heartbeat carries a GAP that spans
// the whole run (docs/endurance.md has the measurements). Readers see one
// data item as several instances.
//
// SpecKeyType replaces getKey() with the computation the RTPS specification
// defines (big-endian CDR of the key fields, padding zero, MD5 when the key
// can exceed 16 bytes) on a buffer local to the call: the same key always
// gives the same handle, in every thread, and matches other DDS vendors.
#pragma once

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>
#include <fastrtps/utils/md5.h>

#include <array>
#include <cstddef>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <stdexcept>

namespace mtc::idl {

// Largest serialised key SpecKeyType handles (the mtc keys are two bounded
// strings of 64 characters: 141 bytes).
inline constexpr std::size_t kMaxKeyBytes = 512;

// Computes the instance handle of `sample` as the RTPS specification does.
template <typename Sample>
void compute_key_hash(const Sample& sample, eprosima::fastrtps::rtps::InstanceHandle_t& handle,
                      bool force_md5) {
  std::array<char, kMaxKeyBytes> buffer{};  // zero: padding bytes are part of the hash
  eprosima::fastcdr::FastBuffer fast_buffer(buffer.data(), buffer.size());
  eprosima::fastcdr::Cdr cdr(fast_buffer, eprosima::fastcdr::Cdr::BIG_ENDIANNESS);
  sample.serializeKey(cdr);
  const auto length = cdr.getSerializedDataLength();
  if (force_md5 || Sample::getKeyMaxCdrSerializedSize() > 16) {
    MD5 md5;
    md5.update(buffer.data(), static_cast<MD5::size_type>(length));
    md5.finalize();
    for (std::size_t i = 0; i < 16; ++i) handle.value[i] = md5.digest[i];
  } else {
    for (std::size_t i = 0; i < 16; ++i) handle.value[i] = static_cast<unsigned char>(buffer[i]);
  }
}

template <typename PubSub>
class SpecKeyType final : public PubSub {
 public:
  using Sample = typename PubSub::type;

  SpecKeyType() {
    if (Sample::getKeyMaxCdrSerializedSize() > kMaxKeyBytes) {
      throw std::logic_error("mtc::idl::SpecKeyType: the key of " + std::string(this->getName()) +
                             " can exceed kMaxKeyBytes");
    }
  }

  // The generated deserialize() turns only a short payload into `false`;
  // any other malformed one (a bad encapsulation header, a string longer
  // than its bound) throws out of the reader's take() and terminates the
  // process. Bytes a peer sent must never do that: they are refused, and the
  // reader drops the sample.
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    try {
      return PubSub::deserialize(payload, data);
    } catch (const eprosima::fastcdr::exception::Exception&) {
      return false;
    }
  }

  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle,
              bool force_md5) override {
    if (!this->m_isGetKeyDefined) return false;
    compute_key_hash(*static_cast<const Sample*>(data), *handle, force_md5);
    return true;
  }
};

// The type support to register for PubSub (a fastddsgen *PubSubType).
template <typename PubSub>
eprosima::fastdds::dds::TypeSupport type_support() {
  return eprosima::fastdds::dds::TypeSupport(new SpecKeyType<PubSub>());
}

}  // namespace mtc::idl
