%% discretisation check: recompute k=10 orbit, an unstable orbit and the fold
% with a finer collocation (degree 4, 120 intervals); needs tau10_results.mat
setup_path(); load('tau10_results.mat'); [funcs,ip]=slope_funcs();
deg=4; nint=120;
fprintf('mesh check: degree %d, %d intervals\n',deg,nint);
pbr.method.point.extra_condition=1;
[k,T]=orbit_measures(pbr.point,ip); [~,ifold]=min(k);
cases={'unstable',4,1:ifold;'stable',10,ifold:numel(k)};
for i=1:size(cases,1)
    [pt,suc]=orbit_at_k(funcs,pbr,ip,cases{i,2},cases{i,3});
    pt=p_remesh(pt,deg,nint);
    [pt,suc]=p_correc(funcs,pt,ip.c,[],pbr.method.point);
    pt.stability=p_stabil(funcs,pt,pbr.method.stability);
    mu=pt.stability.mu; [~,o]=sort(abs(mu-1)); rest=mu(o(3:end));
    fprintf('MESHCHECK %-8s k=%g T=%.8f max|nontriv mu|=%.6f suc=%d\n',cases{i,1},cases{i,2},pt.period,max(abs(rest)),suc);
end
fine.point=arrayfun(@(p)p_remesh(p,deg,nint),fine.point);
fine.method.point.extra_condition=1;
[kp,Tp,~,~,sp]=pofold_point(funcs,fine,ip);
fprintf('MESHCHECK POFOLD success=%d k_fold=%.8f T_fold=%.8f\n',sp,kp,Tp);
