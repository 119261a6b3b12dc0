//! The balloon profiles' part of the store contract (`conformance.rs` runs
//! it against each backend): a profile is its owner's, replaced in place,
//! listed by name, deleted once, and copied to another store as it is.

use super::Store;

pub(super) async fn profiles_are_kept_per_owner_and_replaced_in_place(store: Store, into: Store) {
    let first = r#"{"balloon": {"length_mm": 300}}"#;
    assert!(
        store
            .put_profile("lab", "batch-7", first, None)
            .await
            .unwrap()
    );
    assert!(store.put_profile("lab", "aged", first, None).await.unwrap());
    assert!(
        store
            .put_profile("other", "batch-7", "{}", None)
            .await
            .unwrap()
    );
    let before = store.profile("lab", "batch-7").await.unwrap().unwrap();
    assert_eq!((before.profile.as_str(), before.source_job), (first, None));
    let second = r#"{"balloon": {"length_mm": 310}}"#;
    let job = uuid::Uuid::now_v7().to_string();
    let created = store.put_profile("lab", "batch-7", second, Some(&job));
    assert!(!created.await.unwrap(), "replaced, not created");
    let after = store.profile("lab", "batch-7").await.unwrap().unwrap();
    assert_eq!(after.profile, second);
    assert_eq!(after.source_job.as_deref(), Some(job.as_str()));
    assert_eq!(after.created_at, before.created_at);
    assert!(after.updated_at >= before.updated_at);
    let names: Vec<String> = (store.profiles("lab").await.unwrap())
        .into_iter()
        .map(|p| p.name)
        .collect();
    assert_eq!(names, ["aged", "batch-7"]);
    assert_eq!(
        store
            .profile("other", "batch-7")
            .await
            .unwrap()
            .unwrap()
            .profile,
        "{}"
    );
    assert!(store.profile("nobody", "batch-7").await.unwrap().is_none());
    // Moved to another store as they are, once.
    let all = store.all_profiles().await.unwrap();
    assert_eq!(all.len(), 3);
    for p in &all {
        assert!(into.import_profile(p).await.unwrap());
        assert!(!into.import_profile(p).await.unwrap());
    }
    let copied = into.profile("lab", "batch-7").await.unwrap().unwrap();
    assert_eq!(
        (
            copied.profile,
            copied.source_job,
            copied.created_at,
            copied.updated_at
        ),
        (
            after.profile.clone(),
            after.source_job.clone(),
            after.created_at.clone(),
            after.updated_at.clone()
        )
    );
    assert!(store.delete_profile("lab", "batch-7").await.unwrap());
    assert!(!store.delete_profile("lab", "batch-7").await.unwrap());
    assert!(store.profile("lab", "batch-7").await.unwrap().is_none());
    assert!(store.profile("other", "batch-7").await.unwrap().is_some());
}

/// Profiles saved while other connections write: every save lands, and
/// exactly one save of each name reports it created (a save that read the
/// row and then wrote it could find its snapshot stale on SQLite and fail).
pub(super) async fn profiles_saved_at_once_all_land(store: Store) {
    const WRITERS: usize = 6;
    const SAVES: usize = 15;
    let writers = (0..WRITERS).map(|w| {
        let store = store.clone();
        tokio::spawn(async move {
            let mut created = 0;
            for s in 0..SAVES {
                let name = format!("batch-{}", s % 3);
                let profile = format!("{{\"writer\": {w}, \"save\": {s}}}");
                let put = store.put_profile("lab", &name, &profile, None).await;
                created += usize::from(put.expect("a save beside other writers lands"));
            }
            created
        })
    });
    let mut created = 0;
    for writer in writers.collect::<Vec<_>>() {
        created += writer.await.expect("the writer finishes");
    }
    assert_eq!(created, 3, "each of the three names is created once");
    assert_eq!(store.profiles("lab").await.unwrap().len(), 3);
}
