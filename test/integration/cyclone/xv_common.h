/* The cross-vendor test's sample contents: both ends compute them from the sequence number, so the subscriber
 * can check every byte that went through the gateway. */
#ifndef TGW_XV_COMMON_H
#define TGW_XV_COMMON_H

#include <dds/dds.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Lengths from 1 byte to 5 kB: samples above about 1.4 kB go as DATA_FRAG. */
static inline uint32_t xv_blob_length(uint32_t seq) {
    return 1u + (seq * 997u) % 5000u;
}

static inline uint8_t xv_blob_byte(uint32_t seq, uint32_t index) {
    return (uint8_t)((seq * 31u + index * 7u) & 0xffu);
}

static inline int32_t xv_keyed_id(uint32_t seq, uint32_t instances) {
    return (int32_t)(seq % instances) * 10 + 3;
}

static inline void xv_keyed_text(char* out, size_t size, int32_t id, uint32_t seq) {
    snprintf(out, size, "instance %d, sample %u: payload intact", (int)id, (unsigned)seq);
}

typedef struct xv_args {
    int domain;
    const char* topic;
    int keyed;
    uint32_t count;
    uint32_t instances;
    double seconds;
} xv_args;

/* QoS beyond the defaults, from the environment, the same for both ends:
 *   XV_PARTITION=NAME     the publisher's or subscriber's partition;
 *   XV_TRANSIENT_LOCAL=1  durability transient local (a "latched" publisher, a late-joining reader). */
static inline void xv_apply_env_qos(dds_qos_t* qos) {
    const char* partition = getenv("XV_PARTITION");
    if (partition != NULL && *partition != '\0')
        dds_qset_partition1(qos, partition);
    const char* transient_local = getenv("XV_TRANSIENT_LOCAL");
    if (transient_local != NULL && strcmp(transient_local, "1") == 0)
        dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
}

/* A non-negative integer from the environment, or `otherwise`. */
static inline uint32_t xv_env_uint(const char* name, uint32_t otherwise) {
    const char* value = getenv(name);
    return value != NULL && *value != '\0' ? (uint32_t)strtoul(value, NULL, 10) : otherwise;
}

/* argv: DOMAIN TOPIC blob|keyed COUNT INSTANCES SECONDS */
static inline int xv_parse_args(int argc, char** argv, xv_args* args) {
    if (argc != 7)
        return 0;
    args->domain = atoi(argv[1]);
    args->topic = argv[2];
    args->keyed = strcmp(argv[3], "keyed") == 0;
    args->count = (uint32_t)strtoul(argv[4], NULL, 10);
    args->instances = (uint32_t)strtoul(argv[5], NULL, 10);
    args->seconds = atof(argv[6]);
    return (strcmp(argv[3], "blob") == 0 || args->keyed) && args->count > 0 && args->instances > 0 && args->seconds > 0;
}

#endif
