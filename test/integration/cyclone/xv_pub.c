/* Cyclone DDS publisher for the cross-vendor test: writes samples 0..COUNT-1 of tgw_xv::Blob or
 * tgw_xv::KeyedBlob over and over, with a known source timestamp, until SECONDS have passed. Repeating makes
 * the test independent of when the gateway's reader and writer match. PAUSE_MS (default 20) between samples;
 * 0 writes each round as one burst, whose samples the gateway packs into shared WAN datagrams.
 * XV_ROUNDS=N stops writing after N rounds and stays until SECONDS have passed (a latched publisher's history
 * then stays with it); each round ends with a line "xv_pub: round N written". XV_PARTITION and
 * XV_TRANSIENT_LOCAL: see xv_common.h. XV_WRITE_UNMATCHED=1 writes without waiting for a reader (an intruder's
 * attempt to inject samples into a secured domain, whose readers it never matches). */
#include <dds/dds.h>

#include "CrossVendor.h"
#include "xv_common.h"

int main(int argc, char** argv) {
    xv_args args;
    const int pause_ms = argc == 8 ? atoi(argv[7]) : 20;
    if (!xv_parse_args(argc == 8 ? 7 : argc, argv, &args) || pause_ms < 0) {
        fprintf(stderr, "usage: xv_pub DOMAIN TOPIC blob|keyed COUNT INSTANCES SECONDS [PAUSE_MS]\n");
        return 2;
    }
    const dds_entity_t participant = dds_create_participant((dds_domainid_t)args.domain, NULL, NULL);
    if (participant < 0) {
        fprintf(stderr, "xv_pub: dds_create_participant: %s\n", dds_strretcode(-participant));
        return 1;
    }
    const dds_topic_descriptor_t* desc = args.keyed ? &tgw_xv_KeyedBlob_desc : &tgw_xv_Blob_desc;
    const dds_entity_t topic = dds_create_topic(participant, desc, args.topic, NULL, NULL);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 64);
    xv_apply_env_qos(qos);
    const dds_entity_t writer = dds_create_writer(participant, topic, qos, NULL);
    dds_delete_qos(qos);
    if (topic < 0 || writer < 0) {
        fprintf(stderr, "xv_pub: cannot create topic or writer: %s\n", dds_strretcode(topic < 0 ? -topic : -writer));
        return 1;
    }

    const dds_time_t end = dds_time() + (dds_duration_t)(args.seconds * 1e9);
    uint8_t* buffer = malloc(5001);
    char text[128];
    unsigned long written = 0;
    const uint32_t rounds = xv_env_uint("XV_ROUNDS", UINT32_MAX);
    uint32_t round = 0;
    const int write_unmatched = xv_env_uint("XV_WRITE_UNMATCHED", 0) == 1;
    while (dds_time() < end) {
        if (round >= rounds) {
            dds_sleepfor(DDS_MSECS(50));
            continue;
        }
        dds_publication_matched_status_t matched;
        dds_get_publication_matched_status(writer, &matched);
        if (matched.current_count == 0 && !write_unmatched) {
            dds_sleepfor(DDS_MSECS(50));
            continue;
        }
        for (uint32_t seq = 0; seq < args.count && dds_time() < end; ++seq) {
            const dds_time_t stamp = dds_time();
            dds_return_t rc;
            if (args.keyed) {
                tgw_xv_KeyedBlob sample;
                sample.id = xv_keyed_id(seq, args.instances);
                sample.seq = seq;
                sample.stamp_ns = stamp;
                xv_keyed_text(text, sizeof(text), sample.id, seq);
                sample.text = text;
                rc = dds_write_ts(writer, &sample, stamp);
            } else {
                tgw_xv_Blob sample;
                sample.seq = seq;
                sample.stamp_ns = stamp;
                sample.data._length = sample.data._maximum = xv_blob_length(seq);
                for (uint32_t i = 0; i < sample.data._length; ++i)
                    buffer[i] = xv_blob_byte(seq, i);
                sample.data._buffer = buffer;
                sample.data._release = false;
                rc = dds_write_ts(writer, &sample, stamp);
            }
            if (rc == DDS_RETCODE_OK)
                ++written;
            if (pause_ms > 0)
                dds_sleepfor(DDS_MSECS(pause_ms));
        }
        ++round;
        printf("xv_pub: round %u written\n", round);
        fflush(stdout);
        dds_sleepfor(DDS_MSECS(200));
    }
    free(buffer);
    printf("xv_pub: %s: wrote %lu samples\n", args.topic, written);
    dds_delete(participant);
    return 0;
}
