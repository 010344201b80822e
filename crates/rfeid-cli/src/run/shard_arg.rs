//! `--shard K/N` (or `auto`, from Slurm's job-array variables).
use crate::diagnostics::Failure;

/// Parses `K/N` (0 ≤ K < N) or `auto` (from Slurm's job-array variables).
pub fn parse_shard(text: &str) -> Result<(usize, usize), Failure> {
    if text == "auto" {
        return from_slurm();
    }
    let bad = || {
        Failure::input_msg(format!(
            "--shard '{text}': expected K/N with 0 <= K < N (e.g. 0/4), or auto"
        ))
    };
    let (k, n) = text.split_once('/').ok_or_else(bad)?;
    let k: usize = k.trim().parse().map_err(|_| bad())?;
    let n: usize = n.trim().parse().map_err(|_| bad())?;
    checked(k, n, text)
}

/// `--shard auto`: the shard of this task of a Slurm job array.
fn from_slurm() -> Result<(usize, usize), Failure> {
    let var = |name: &str| -> Result<Option<usize>, Failure> {
        match std::env::var(name) {
            Err(_) => Ok(None),
            Ok(v) => v.trim().parse().map(Some).map_err(|_| {
                Failure::input_msg(format!("--shard auto: {name}='{v}' is not a count"))
            }),
        }
    };
    let (Some(id), Some(count)) = (var("SLURM_ARRAY_TASK_ID")?, var("SLURM_ARRAY_TASK_COUNT")?)
    else {
        return Err(Failure::input_msg(
            "--shard auto: SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT are not set (not in a Slurm job array?)",
        ));
    };
    let min = var("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
    let k = id.checked_sub(min).ok_or_else(|| {
        Failure::input_msg(format!(
            "--shard auto: SLURM_ARRAY_TASK_ID {id} is below SLURM_ARRAY_TASK_MIN {min}"
        ))
    })?;
    checked(k, count, "auto")
}

/// Shard `k` of `n` must exist.
fn checked(k: usize, n: usize, text: &str) -> Result<(usize, usize), Failure> {
    if n == 0 || k >= n {
        return Err(Failure::input_msg(format!(
            "--shard {text}: shard {k} of {n} does not exist (0 <= K < N)"
        )));
    }
    Ok((k, n))
}
