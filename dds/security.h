#pragma once
// DDS Security for a participant, from an SROS2-style enclave directory:
//   cert.pem, key.pem            the participant's identity (PKI-DH authentication)
//   identity_ca.cert.pem         the CA that signs every identity of the deployment
//   permissions_ca.cert.pem      the CA that signs governance and permissions
//   governance.p7s               domain rules (S/MIME signed): who may join, what is encrypted
//   permissions.p7s              this identity's grants (S/MIME signed)
// With it, Fast DDS's builtin PKI-DH, Access-Permissions and AES-GCM-GMAC plugins authenticate
// every participant, enforce the grants and encrypt the traffic; a participant without
// credentials the deployment's CAs signed cannot join, read or write. scripts/make-keystore
// makes such enclaves.
#include <string>

#include <fastdds/dds/core/policy/QosPolicies.hpp>

namespace navd::dds {

// Adds the security properties for `enclave_dir` to `properties`. Throws std::invalid_argument
// naming the first file that is missing or unreadable.
void AddSecurityProperties(const std::string& enclave_dir, eprosima::fastdds::dds::PropertyPolicyQos& properties);

}  // namespace navd::dds
