import json,sys,re
rows=[]
print("scene,target,before_rmse,before_rmse_over_t,before_maps,before_ms,after_rmse,after_rmse_over_t,after_maps,after_ms,after_density,after_predicted_map")
for s in ["pergola-garden","canopy-market","default","cows"]:
    b=[json.loads(l) for l in open(f"OUT/before-{s}/results.jsonl")]
    a=[json.loads(l) for l in open(f"OUT/after-{s}/results.jsonl")]
    for rb,ra in zip(b,a):
        t=rb['params']['target']; t=round(t,4)
        rec=ra.get('method_record',{})
        print(f"{s},{t},{rb['metrics']['rmse']:.5f},{rb['metrics']['rmse']/t:.2f},{rb['shadow_maps']},{rb['total_ms']:.0f},{ra['metrics']['rmse']:.5f},{ra['metrics']['rmse']/t:.2f},{ra['shadow_maps']},{ra['total_ms']:.0f},{rec.get('density','')},{rec.get('predicted_map','')}")
