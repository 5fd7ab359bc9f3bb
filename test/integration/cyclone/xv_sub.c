/* Cyclone DDS subscriber for the cross-vendor test: waits until it has received every sample 0..COUNT-1 and
 * checks each byte, the source timestamp, and for keyed topics that each key keeps one instance of its own.
 * Exit 0 when all arrived intact, 1 on a corrupted sample or after SECONDS without all of them.
 * XV_FIRST=N expects only samples N..COUNT-1: an earlier one is an error (a late joiner to a latched topic gets
 * the last sample of each instance, nothing older). XV_EXPECT_NONE=1 passes only if nothing arrives within
 * SECONDS (a reader outside the publisher's partition). XV_WATCH=1 listens for SECONDS whatever arrives and passes
 * unless a sample is corrupted or numbered COUNT or more (what an intruder injected past what the robot sends).
 * XV_PARTITION and XV_TRANSIENT_LOCAL: see xv_common.h. */
#include <dds/dds.h>

#include "CrossVendor.h"
#include "xv_common.h"

#define MAX_SAMPLES 16

static int check_blob(const tgw_xv_Blob* s, const dds_sample_info_t* info) {
    if (s->data._length != xv_blob_length(s->seq)) {
        fprintf(stderr, "xv_sub: sample %u: %u bytes, expected %u\n", s->seq, s->data._length, xv_blob_length(s->seq));
        return 0;
    }
    for (uint32_t i = 0; i < s->data._length; ++i) {
        if (s->data._buffer[i] != xv_blob_byte(s->seq, i)) {
            fprintf(stderr, "xv_sub: sample %u: byte %u differs\n", s->seq, i);
            return 0;
        }
    }
    if (info->source_timestamp != s->stamp_ns) {
        fprintf(stderr, "xv_sub: sample %u: source timestamp %lld, written with %lld\n", s->seq,
                (long long)info->source_timestamp, (long long)s->stamp_ns);
        return 0;
    }
    return 1;
}

static int check_keyed(const tgw_xv_KeyedBlob* s, const dds_sample_info_t* info, uint32_t instances,
                       dds_instance_handle_t* handles) {
    char expected[128];
    if (s->id != xv_keyed_id(s->seq, instances)) {
        fprintf(stderr, "xv_sub: sample %u: id %d, expected %d\n", s->seq, s->id, xv_keyed_id(s->seq, instances));
        return 0;
    }
    xv_keyed_text(expected, sizeof(expected), s->id, s->seq);
    if (s->text == NULL || strcmp(s->text, expected) != 0) {
        fprintf(stderr, "xv_sub: sample %u: text '%s', expected '%s'\n", s->seq, s->text ? s->text : "(null)",
                expected);
        return 0;
    }
    if (info->source_timestamp != s->stamp_ns) {
        fprintf(stderr, "xv_sub: sample %u: source timestamp differs\n", s->seq);
        return 0;
    }
    /* One instance per key: the same key always arrives with the same handle, different keys never share one. */
    const uint32_t slot = s->seq % instances;
    if (handles[slot] == 0) {
        for (uint32_t i = 0; i < instances; ++i) {
            if (handles[i] == info->instance_handle) {
                fprintf(stderr, "xv_sub: keys %d and %d share an instance\n", xv_keyed_id(i, instances), s->id);
                return 0;
            }
        }
        handles[slot] = info->instance_handle;
    } else if (handles[slot] != info->instance_handle) {
        fprintf(stderr, "xv_sub: key %d changed instance\n", s->id);
        return 0;
    }
    return 1;
}

int main(int argc, char** argv) {
    xv_args args;
    if (!xv_parse_args(argc, argv, &args)) {
        fprintf(stderr, "usage: xv_sub DOMAIN TOPIC blob|keyed COUNT INSTANCES SECONDS\n");
        return 2;
    }
    const dds_entity_t participant = dds_create_participant((dds_domainid_t)args.domain, NULL, NULL);
    if (participant < 0) {
        fprintf(stderr, "xv_sub: dds_create_participant: %s\n", dds_strretcode(-participant));
        return 1;
    }
    const dds_topic_descriptor_t* desc = args.keyed ? &tgw_xv_KeyedBlob_desc : &tgw_xv_Blob_desc;
    const dds_entity_t topic = dds_create_topic(participant, desc, args.topic, NULL, NULL);
    dds_qos_t* qos = dds_create_qos();
    /* Reliable, as ROS 2 and ddsperf readers are: it matches only because the gateway's WAN writer offers what
     * the (reliable) Cyclone publisher offered. */
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
    xv_apply_env_qos(qos);
    const dds_entity_t reader = dds_create_reader(participant, topic, qos, NULL);
    dds_delete_qos(qos);
    if (topic < 0 || reader < 0) {
        fprintf(stderr, "xv_sub: cannot create topic or reader: %s\n", dds_strretcode(topic < 0 ? -topic : -reader));
        return 1;
    }

    const uint32_t first = xv_env_uint("XV_FIRST", 0);
    const int expect_none = xv_env_uint("XV_EXPECT_NONE", 0) == 1;
    const int watch = xv_env_uint("XV_WATCH", 0) == 1;
    const uint32_t expected = expect_none ? 0 : args.count - (first < args.count ? first : args.count);
    uint8_t* seen = calloc(args.count, 1);
    dds_instance_handle_t* handles = calloc(args.instances, sizeof(dds_instance_handle_t));
    uint32_t distinct = 0;
    unsigned long received = 0;
    int ok = 1;
    void* samples[MAX_SAMPLES] = {NULL};
    dds_sample_info_t infos[MAX_SAMPLES];
    const dds_time_t end = dds_time() + (dds_duration_t)(args.seconds * 1e9);
    while (ok && (expect_none || watch || distinct < expected) && dds_time() < end) {
        const dds_return_t n = dds_take(reader, samples, infos, MAX_SAMPLES, MAX_SAMPLES);
        if (n <= 0) {
            dds_sleepfor(DDS_MSECS(20));
            continue;
        }
        for (dds_return_t i = 0; i < n && ok; ++i) {
            if (!infos[i].valid_data)
                continue;
            ++received;
            uint32_t seq;
            if (args.keyed) {
                const tgw_xv_KeyedBlob* s = samples[i];
                seq = s->seq;
                ok = seq < args.count && check_keyed(s, &infos[i], args.instances, handles);
            } else {
                const tgw_xv_Blob* s = samples[i];
                seq = s->seq;
                ok = seq < args.count && check_blob(s, &infos[i]);
            }
            if (ok && (expect_none || seq < first)) {
                fprintf(stderr, "xv_sub: sample %u arrived, expected %s\n", seq,
                        expect_none ? "none" : "only the latest of each instance");
                ok = 0;
            }
            if (ok && !seen[seq]) {
                seen[seq] = 1;
                ++distinct;
            }
        }
        dds_return_loan(reader, samples, n);
    }
    printf("xv_sub: %s: %lu samples received, %u of %u expected distinct, %s\n", args.topic, received, distinct,
           expected,
           !ok                   ? "UNEXPECTED"
           : expect_none         ? "none, as expected"
           : watch               ? "none numbered past the robot's, as expected"
           : distinct == expected ? "all intact"
                                 : "TIMED OUT");
    free(seen);
    free(handles);
    dds_delete(participant);
    return ok && (watch || distinct == expected) ? 0 : 1;
}
